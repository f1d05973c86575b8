# Section vivid: two vivid instances, each a capture + an output node, in
# loopback.
#  1. v4l2_loop check writes generated stereo pairs (left/right, frame
#     counter) into /dev/video2 + /dev/video3 and captures them on
#     /dev/video0 + /dev/video1 (mmap streaming, 3-4 buffers, poll timeout);
#     every captured frame must be byte-identical to an injected one of the
#     same eye, in GREY and in YUYV.
#  2. the drop-in path: `v4l2_loop inject` runs in the background and a
#     separate process (`v4l2_loop capture`, standing in for negobs_run) only
#     sets the format and streams; its frames must be the injected ones.
#  3. recorded frames: the 6+6 frames it saved (-O) are injected from files
#     (-L/-R, the path for recorded stereo pairs) and must come back intact.
set -e
. /tests/lib.sh
hw_vivid_load
v4l2_loop check -f GREY -n 8 -b 4 -T 5000 -q /dev/video0 /dev/video1 /dev/video2 /dev/video3
v4l2_loop check -f YUYV -n 6 -b 3 -T 5000 -q /dev/video0 /dev/video1 /dev/video2 /dev/video3
hw_inject_start -f GREY
rc=0
mkdir -p /tmp/rec
v4l2_loop capture -f GREY -n 6 -b 4 -T 5000 -q -O /tmp/rec /dev/video0 /dev/video1 || rc=$?
hw_inject_stop
[ $rc -eq 0 ] || exit $rc
cat /tmp/rec/left_*.raw > /tmp/left.raw
cat /tmp/rec/right_*.raw > /tmp/right.raw
hw_inject_start -f GREY -L /tmp/left.raw -R /tmp/right.raw
v4l2_loop capture -f GREY -n 6 -b 4 -T 5000 -q /dev/video0 /dev/video1 || rc=$?
hw_inject_stop
exit $rc
