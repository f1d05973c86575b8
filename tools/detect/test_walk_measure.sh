#!/bin/sh
# The rendered-walk measurements of tools/synth run and read what they
# should. Exit 77 (skipped) when python3-opencv is missing.
#
#   floor  floor_noise.py on one asphalt walk (B = 12 cm, 2 frames): it
#          prints the three matchers, and negobs's 16-px strip medians
#          scatter by less than 0.1 px (0.04 px measured; a matcher that
#          lost sub-pixel precision reads 0.2-0.3).
#   pool   pool_noise.py on one smooth-concrete walk (B = 12 cm, 16
#          frames): a floor patch's error is nearly independent from frame
#          to frame (correlation below 0.3; 0.05 measured) and its mean
#          over 4 frames scatters at most 0.7 x one frame's (0.5 measured,
#          1/sqrt 4 for independent frames). This is what makes pooling
#          frames worth building; a renderer or matcher whose errors
#          followed the floor would fail it.
#
# usage: test_walk_measure.sh floor|pool SCRIPT_PY BUILD_DIR WORK_DIR
set -u
mode=$1 py=$2 build=$3 work=$4
rm -rf "$work"
pyi=python3; [ -x /usr/bin/python3 ] && pyi=/usr/bin/python3  # the Debian one has cv2
case $mode in
floor) out=$("$pyi" "$py" --build "$build" --textures asphalt --baselines 120 --frames 2 --work "$work") ;;
pool) out=$("$pyi" "$py" --build "$build" --textures concrete --baselines 120 --frames 16 --work "$work") ;;
*) echo "usage: test_walk_measure.sh floor|pool SCRIPT_PY BUILD_DIR WORK_DIR"; exit 2 ;;
esac
rc=$?
[ "$rc" -eq 77 ] && { echo "skipped: python3-opencv missing"; exit 77; }
echo "$out"
[ "$rc" -eq 0 ] || { echo "FAIL: $(basename "$py") exit $rc"; exit 1; }
if [ "$mode" = floor ]; then
    for m in negobs bm sgbm; do
        echo "$out" | grep -q "^asphalt  *120  $m " || { echo "FAIL: no $m row"; exit 1; }
    done
    echo "$out" | awk '$1 == "asphalt" && $3 == "negobs" { sd = $7 }
        END { if (sd == "" || sd + 0 >= 0.1) { print "FAIL: negobs strip sd " sd " px"; exit 1 }
              print "negobs strip sd " sd " px < 0.1" }'
else
    echo "$out" | awk '$1 == "concrete" && $3 == "2-3" { sd1 = $5; corr = $6; sd4 = $8 }
        END {
          if (sd1 == "") { print "FAIL: no concrete 2-3 m row"; exit 1 }
          if (corr + 0 >= 0.3) { print "FAIL: frame-to-frame correlation " corr; exit 1 }
          if (sd4 + 0 > 0.7 * sd1) { print "FAIL: sd4 " sd4 " > 0.7 x sd1 " sd1; exit 1 }
          print "corr " corr " < 0.3; sd4 " sd4 " <= 0.7 x sd1 " sd1 }'
fi
