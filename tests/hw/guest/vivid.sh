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
set -e
. /tests/lib.sh
hw_vivid_load
v4l2_loop check -f GREY -n 8 -b 4 -T 5000 -q /dev/video0 /dev/video1 /dev/video2 /dev/video3
v4l2_loop check -f YUYV -n 4 -b 3 -T 5000 -q /dev/video0 /dev/video1 /dev/video2 /dev/video3
hw_inject_start -f GREY
rc=0
v4l2_loop capture -f GREY -n 6 -b 4 -T 5000 -q /dev/video0 /dev/video1 || rc=$?
hw_inject_stop
exit $rc
