#!/bin/sh
# negobs_eval --score on opencv-doc's aloe pair: the map negobs_stereo
# writes, in each of its formats, must score exactly as negobs_eval's own
# negobs row for the set (same engine, same range, same GT), in CSV and
# JSON; a mask restricts the pixels; bad input exits 1, bad usage 2.
# usage: test_score.sh NEGOBS_STEREO NEGOBS_EVAL OPENCV_DOC_DIR WORKDIR
set -u
st=$1 ev=$2 doc=$3 w=$4
for f in aloeL.jpg aloeR.jpg aloeGT.png; do
    [ -f "$doc/$f" ] || { echo "skipped: $doc/$f absent"; exit 77; }
done
rm -rf "$w" && mkdir -p "$w" || exit 1
fail=0
ok() { echo "ok - $*"; }
bad() { echo "FAIL - $*"; fail=1; }

# the built-in evaluation's negobs row (columns 5.. = evaluated px onwards)
"$ev" --set aloe-opencv-doc --matchers negobs --repeat 1 --csv "$w/ref.csv" \
    >/dev/null || { echo "FAIL - negobs_eval --set aloe-opencv-doc"; exit 1; }
ref=$(sed -n 2p "$w/ref.csv" | cut -d, -f5-10)
[ -n "$ref" ] && ok "reference row: $ref" || bad "no reference row"

for fmt in png16 kitti pfm; do
    ext=png; [ $fmt = pfm ] && ext=pfm
    "$st" "$doc/aloeL.jpg" "$doc/aloeR.jpg" "$w/map_$fmt.$ext" --max-disp 211 \
        --dense --format=$fmt || { bad "negobs_stereo --format=$fmt"; continue; }
    "$ev" --score "$w/map_$fmt.$ext" -f $fmt --gt "$doc/aloeGT.png" \
        --csv "$w/$fmt.csv" --json "$w/$fmt.json" >/dev/null ||
        { bad "negobs_eval --score ($fmt) failed"; continue; }
    got=$(sed -n 2p "$w/$fmt.csv" | cut -d, -f5-10)
    [ "$got" = "$ref" ] && ok "$fmt scores as the built-in row" ||
        bad "$fmt: got $got, want $ref"
    grep -q "\"bad1_pct\": $(echo "$ref" | cut -d, -f3)," "$w/$fmt.json" &&
        ok "$fmt JSON has the same bad1" || bad "$fmt JSON differs: $(cat "$w/$fmt.json")"
done

# a mask evaluates only its 255 pixels
"$ev" --score "$w/map_png16.png" --gt "$doc/aloeGT.png" --csv "$w/all.csv" >/dev/null
# the engine's confidence map as the mask: 255 only where the match
# scored highest, a small part of the frame
"$st" "$doc/aloeL.jpg" "$doc/aloeR.jpg" "$w/c.png" --max-disp 211 --dense \
    --confidence "$w/conf.png" >/dev/null 2>&1
"$ev" --score "$w/map_png16.png" --gt "$doc/aloeGT.png" --mask "$w/conf.png" \
    --csv "$w/mask.csv" >/dev/null || bad "--mask run failed"
n_all=$(sed -n 2p "$w/all.csv" | cut -d, -f5)
n_mask=$(sed -n 2p "$w/mask.csv" | cut -d, -f5)
[ -n "$n_mask" ] && [ "$n_mask" -gt 0 ] && [ "$n_mask" -lt "$n_all" ] &&
    ok "--mask evaluates $n_mask of $n_all px" || bad "--mask: $n_mask of $n_all"

# errors: size mismatch / unreadable -> 1, usage -> 2
"$ev" --score "$w/map_png16.png" --gt "$doc/left01.jpg" >/dev/null 2>&1
rc=$?; [ $rc -eq 1 ] && ok "size mismatch exits 1" || bad "size mismatch exit $rc"
"$ev" --score "$w/none.pfm" --gt "$doc/aloeGT.png" >/dev/null 2>&1
rc=$?; [ $rc -eq 1 ] && ok "unreadable map exits 1" || bad "unreadable map exit $rc"
"$ev" --score "$w/map_png16.png" >/dev/null 2>&1
rc=$?; [ $rc -eq 2 ] && ok "--score without --gt exits 2" || bad "no --gt exit $rc"
"$ev" --score "$w/map_png16.png" --gt "$doc/aloeGT.png" --format tiff >/dev/null 2>&1
rc=$?; [ $rc -eq 2 ] && ok "--format tiff exits 2" || bad "--format tiff exit $rc"
exit $fail
