# Section libcamera-vimc: one camera through negobs' libcamera backend.
# vimc (built out of tree) provides the media graph; Debian's libcamera
# 0.0.3 with its vimc pipeline handler and IPA sees one camera on it
# ('Sensor B'; libcamera cannot pair two, so this is single-camera
# capture). lc_capture (tests/hw/guest/lc_capture.c, linked with
# port/camera/libcamera) opens it by index (stopping and starting it once
# halfway) and then by id, and checks N frames: requested size, advancing
# timestamps and sequence numbers, content that is not flat. The sizes are
# ones vimc's pipeline handler keeps as asked (asked for 640x480 it
# configured 636x480); the backend hands on what libcamera configured, so
# an adjusted size fails the check rather than passing unnoticed.
# Exit 0 pass, 77 skip (reason on the last line), else fail.
set -e
. /tests/lib.sh
[ -x /bin/lc_capture ] || { echo "lc_capture not in the initramfs"; exit 77; }
modprobe vimc || { echo "modprobe vimc failed"; exit 1; }
# vivid (earlier sections) has media devices too: wait for vimc's own,
# the one whose parent is the vimc.0 platform device
vimc_media() {
    for m in /sys/bus/media/devices/media*; do
        case "$(readlink -f "$m")" in */vimc.0/media*) echo "${m##*/}"; return ;; esac
    done
}
d=$(hw_deadline 10)
while [ -z "$(vimc_media)" ] && hw_before "$d"; do sleep 0.1; done
[ -n "$(vimc_media)" ] || { echo "vimc: no media device under vimc.0"; ls -l /sys/bus/media/devices/; exit 1; }
echo "vimc: /dev/$(vimc_media), $(ls /dev | grep -c '^v4l-subdev') sub-devices in /dev"
export LD_LIBRARY_PATH=/lib/aarch64-linux-gnu
export LIBCAMERA_LOG_LEVELS='*:ERROR'
# 12 frames: more than the frozen-stream limit (10 identical frames);
# vimc's frames differ from one to the next, so a live stream must not be
# called frozen
lc_capture -n 12 -w 636 -h 480 -T 30000 -R libcamera:0
# the same camera by its id, as `cam -l` names it
lc_capture -n 3 -w 480 -h 360 -T 30000 'libcamera:platform/vimc.0 Sensor B'
# errors on the real camera list: an absent index, a stereo pair where
# libcamera has one camera, and the same camera twice
lc_capture -E -8 libcamera:5
lc_capture -E -8 -r libcamera:1 libcamera:0
lc_capture -E -1 -r 'libcamera:platform/vimc.0 Sensor B' libcamera:0
