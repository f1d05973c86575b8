# Section run-fmt-y16: two Y16 cameras (16-bit little-endian mono, as
# OV9281-class modules deliver through UVC) at 640x480, binned 2x2 to
# 320x240: the mean of each bin, then the top 8 bits (>> 8).  The two vivid
# instances run on their own clocks, so a pair taken while the injector
# moves to the next frame may mix two frames: all but two pairs (one per
# change of frame) must match.
set -u
SECTION=run-fmt-y16
. /tests/lib.sh
. /tests/negobs_lib.sh
. /tests/run-fmt-lib.sh
negobs_prereq
fmt_run Y16 640 480 $F/y16-left.raw $F/y16-right.raw /dev/video0 /dev/video1 || exit 1
fmt_check "Y16  640x480 -> 320x240 per eye (2x2 bins, crop at 0,0)" all-2
exit $RC
