# Section run-fmt-y10: two Y10 cameras (10 bits in 16-bit words) at
# 640x480, binned 2x2 to 320x240: the mean of each bin, then >> 2.
# Otherwise as run-fmt-y16.
set -u
SECTION=run-fmt-y10
. /tests/lib.sh
. /tests/negobs_lib.sh
. /tests/run-fmt-lib.sh
negobs_prereq
fmt_run Y10 640 480 $F/y10-left.raw $F/y10-right.raw /dev/video0 /dev/video1 || exit 1
fmt_check "Y10  640x480 -> 320x240 per eye (2x2 bins, crop at 0,0)" all-2
exit $RC
