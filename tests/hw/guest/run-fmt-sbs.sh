# Section run-fmt-sbs: a side-by-side stereo camera on one node (ELP /
# Arducam style, here 1280x720 GREY: two 640x720 eyes; vivid loops
# 1280x720p60).  negobs_run is given /dev/video0 alone, so it splits each
# frame into its halves, centre-crops each 640x720 eye to 640x480 (rows
# 120..599) and bins it 2x2 to 320x240.  Both eyes come from one frame, so
# every recorded pair must have left and right from the same frame.
set -u
SECTION=run-fmt-sbs
. /tests/lib.sh
. /tests/negobs_lib.sh
. /tests/run-fmt-lib.sh
negobs_prereq
# 1280x720 frames cost TCG more than 640x480 ones (vivid copies each one
# in the kernel): a 20 s run once recorded only 2 pairs, so 30 s here
RUN_S=30 fmt_run GREY 1280 720 $F/sbs.raw $F/sbs.raw /dev/video0 || exit 1
fmt_check "GREY 1280x720 side by side -> 320x240 per eye (2x2 bins, crop at 0,120)" all
exit $RC
