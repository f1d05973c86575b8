# Section vivid: two vivid instances, each a capture + an output node, in
# loopback.  v4l2_loop writes generated stereo pairs (left/right, frame
# counter) into /dev/video2 + /dev/video3 and captures them on /dev/video0 +
# /dev/video1 (mmap streaming, 4 buffers, poll timeout); every captured
# frame must be byte-identical to an injected one of the same eye.
set -e
modprobe vivid n_devs=2 node_types=0x101,0x101 vid_cap_nr=0,1 vid_out_nr=2,3 no_error_inj=1
for i in 0 1 2 3; do
    n=0
    while [ ! -e /dev/video$i ] && [ $n -lt 50 ]; do sleep 0.1; n=$((n + 1)); done
done
ls -l /dev/video*
v4l2_loop check -f GREY -n 8 -b 4 -T 5000 -q /dev/video0 /dev/video1 /dev/video2 /dev/video3
v4l2_loop check -f YUYV -n 4 -b 3 -T 5000 -q /dev/video0 /dev/video1 /dev/video2 /dev/video3
