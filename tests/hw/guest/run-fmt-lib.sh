# Helpers of the run-fmt-* sections (issue 24: the camera formats through
# vivid's loopback).  Source after /tests/lib.sh and /tests/negobs_lib.sh.
# Each section plays three curb frames (tests/hw/fmtraw.py) in one camera
# format through vivid's output nodes, runs the real negobs_run with that
# pixel_format and capture size (2x2 binned to the 320x240 processing
# size), and checks the pairs it recorded (--record) against the original
# 320x240 frames, pixel for pixel: the format, the split of a side-by-side
# frame, the crop and the binning all have to be right for that.

F=$NEGOBS/fmt
RC=0
fail() { echo "$SECTION: FAIL: $*"; RC=1; }
say() { echo "$SECTION: $*"; }

# fmt_run FORMAT W H LEFT.raw RIGHT.raw NODE...: the injector plays the
# files (each frame held HOLD_MS, then the last one), negobs_run takes
# FORMAT at W x H from NODE... (one node: side by side) for RUN_S seconds
fmt_run() {
    fmt=$1 w=$2 h=$3 lf=$4 rf=$5
    shift 5
    [ -f "$lf" ] && [ -f "$rf" ] || { fail "no $lf / $rf in the image"; return 1; }
    negobs_vivid_load || { fail "vivid did not load"; return 1; }
    # focal_px is the captured eye's: 500 px at 640 wide is the synth
    # rig's 250 px after the 2x2 bins
    { cat $NEGOBS/rig.conf
      echo "capture_width = $w"; echo "capture_height = $h"; echo "pixel_format = $fmt"
      echo "focal_px = 500"; echo "watchdog_ms = 5000"; echo "max_frame_age_ms = 5000"
      echo "pair_tolerance_ms = 20"; echo "record = /tmp/rec"; } > /tmp/fmt.conf
    rm -rf /tmp/rec /tmp/negobs.log
    hw_inject_start -f "$fmt" -W "$w" -H "$h" -L "$lf" -R "$rf" -P "${HOLD_MS:-3000}" ||
        { fail "injector did not start"; return 1; }
    T_START=$(now)
    $NEGOBS/negobs_run --config /tmp/fmt.conf --alert none "$@" 2> /tmp/negobs.log &
    NEGOBS_PID=$!
    say "negobs_run $fmt ${w}x${h} from $*"
    hw_sleep "${RUN_S:-20}"
    negobs_stop || fail "negobs_run did not end cleanly"
    hw_inject_stop
}

# fmt_check GEOMETRY SAME_MIN: the log names the capture geometry
# (GEOMETRY, e.g. "GREY 1280x720 side by side -> 320x240 per eye (2x2 bins,
# crop at 0,120)"); at least 2 pairs recorded, every eye of every pair
# byte-identical to an original frame, and at least SAME_MIN pairs (a
# number, "all", or "all-N": all but N) with left and right from the same frame
fmt_check() {
    grep -qF "camera: $1" /tmp/negobs.log || fail "no 'camera: $1' in the log"
    np=$(grep -vc '^#' /tmp/rec/frames.txt 2>/dev/null)
    np=${np:-0}
    exact=0 same=0 i=0
    : > /tmp/fmt.pairs
    while [ "$i" -lt "$np" ]; do
        l=$(dd if=/tmp/rec/left.y bs=76800 skip=$i count=1 2>/dev/null | md5sum | cut -d' ' -f1)
        r=$(dd if=/tmp/rec/right.y bs=76800 skip=$i count=1 2>/dev/null | md5sum | cut -d' ' -f1)
        li=$(awk -v m="$l" '$1 == m { print $2; exit }' $F/left.md5)
        ri=$(awk -v m="$r" '$1 == m { print $2; exit }' $F/right.md5)
        echo "${li:-none}/${ri:-none}" >> /tmp/fmt.pairs
        [ -n "$li" ] && [ -n "$ri" ] && exact=$((exact + 1))
        [ -n "$li" ] && [ "$li" = "$ri" ] && same=$((same + 1))
        i=$((i + 1))
    done
    say "recorded pairs by original frame (left/right, none = no match): $(sort /tmp/fmt.pairs | uniq -c | awk '{ printf "%s x%s  ", $2, $1 }')"
    say "$exact of $np recorded pairs pixel-identical to the original frames, $same with left and right from the same frame"
    [ "$np" -ge 2 ] || fail "only $np pairs recorded"
    [ "$exact" -eq "$np" ] || fail "$((np - exact)) recorded pairs differ from every original frame"
    case $2 in
        all) want=$np ;;
        all-*) want=$((np - ${2#all-})) ;;
        *) want=$2 ;;
    esac
    [ "$same" -ge "$want" ] || fail "only $same pairs with left and right from the same frame (want $want)"
    [ "$NEGOBS_RC" -eq 0 ] || fail "negobs_run exit status $NEGOBS_RC"
}
