#!/usr/bin/env bash
# Host side of the libcamera-vimc section (called by tests/hw/run.sh after
# its kernel, private arm64 apt lists and kbuild headers are in WORK):
#
#   WORK/libcamera/vimc.ko    vimc, built out of tree from linux-source-6.1
#                             (Debian's kernels do not enable it)
#   WORK/libcamera/root/      overlay for the initramfs:
#     bin/lc_capture          tests/hw/guest/lc_capture.c + negobs' libcamera
#                             backend, cross-built (C99 + C++17) against
#                             Debian's arm64 libcamera 0.0.3, dynamic
#     lib/aarch64-linux-gnu/  every shared library it, the vimc IPA module
#                             and the IPA proxy worker need (NEEDED closure,
#                             resolved in the unpacked arm64 .debs)
#     usr/lib/aarch64-linux-gnu/libcamera/{ipa_vimc.so(.sign),vimc_ipa_proxy},
#     usr/share/libcamera/ipa/vimc/
#                             libcamera's vimc pipeline handler refuses the
#                             camera without its IPA
#
# libudev: the guest runs no udev daemon, and libcamera's udev enumerator
# lists only devices udev has initialised (none). libcamera falls back to
# its sysfs enumerator when udev_new() fails, so the guest gets a stub
# libudev.so.1 (generated from the udev_* symbols libcamera imports) whose
# udev_new() returns NULL. Everything else is Debian's real binaries.
#
# usage: bash tests/hw/build_libcamera.sh WORK KVER KPKGVER
# exit 0 ok; 77 when a prerequisite is missing (reason on the last line);
# other = build failure.
set -u -o pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
HW=$ROOT/tests/hw
WORK=$1 KVER=$2 KPKGVER=$3
OUT=$WORK/libcamera
SYS=$OUT/sysroot
LR=$OUT/root
ML=aarch64-linux-gnu
mkdir -p "$OUT"

skip() { echo "$*"; exit 77; }
for t in aarch64-linux-gnu-g++ aarch64-linux-gnu-gcc aarch64-linux-gnu-readelf make dpkg-deb; do
  command -v "$t" > /dev/null || skip "$t missing (apt-get install g++-aarch64-linux-gnu)"
done

APTD=$WORK/apt-arm64
APTO=(-o APT::Architecture=arm64 -o APT::Architectures=arm64
      -o Dir::Etc::sourcelist="$APTD/sources.list" -o Dir::Etc::sourceparts="$APTD/parts"
      -o Dir::State::Lists="$APTD/lists" -o Dir::Cache="$APTD/cache"
      -o Dir::State::status="$APTD/status" -o Debug::NoLocking=1)
[[ -f $APTD/sources.list ]] || skip "no private arm64 apt configuration in $APTD"
retry() {
  local i
  for i in 1 2 3; do "$@" && return 0; sleep $((i * 2)); done
  return 1
}

# ---- 1. vimc.ko ---------------------------------------------------------
HDR=$WORK/headers
KB=$HDR/usr/src/linux-headers-$KVER
[[ $(cat "$HDR/.version" 2>/dev/null) == "$KVER $KPKGVER" && -f $KB/Makefile ]] ||
  skip "kbuild headers for $KVER not prepared (run.sh's module build failed)"
VM=$OUT/vimc
if [[ ! -f $OUT/vimc.ko || $(cat "$OUT/.vimc-version" 2>/dev/null) != "$KVER $KPKGVER" ]]; then
  SRC_DEB=$WORK/debs/linux-source-6.1_${KPKGVER}_all.deb
  if [[ ! -f $SRC_DEB ]]; then
    (cd "$WORK/debs" && retry apt-get "${APTO[@]}" download -qq "linux-source-6.1=$KPKGVER") ||
      skip "cannot download linux-source-6.1=$KPKGVER (for vimc)"
  fi
  echo "extracting vimc from linux-source-6.1"
  rm -rf "$VM" "$OUT/src" && mkdir -p "$OUT/src"
  dpkg-deb --fsys-tarfile "$SRC_DEB" | tar -xO ./usr/src/linux-source-6.1.tar.xz |
    tar -xJ -C "$OUT/src" linux-source-6.1/drivers/media/test-drivers/vimc || exit 1
  cp -r "$OUT/src/linux-source-6.1/drivers/media/test-drivers/vimc" "$VM"
  echo "building vimc.ko"
  make -s -C "$KB" M="$VM" DEB_BUILD_ARCH="$(dpkg --print-architecture)" DEB_HOST_ARCH=arm64 \
    DEB_HOST_GNU_TYPE=aarch64-linux-gnu CONFIG_VIDEO_VIMC=m modules || exit 1
  cp "$VM/vimc.ko" "$OUT/vimc.ko" && echo "$KVER $KPKGVER" > "$OUT/.vimc-version"
fi

# ---- 2. Debian's arm64 libcamera and its run-time closure ----------------
PKGS=(libcamera0.0.3 libcamera-ipa libcamera-dev)
DEBS=$OUT/debs
mkdir -p "$DEBS"
if [[ ! -f $SYS/.done ]]; then
  echo "resolving ${PKGS[*]} (arm64) against an empty system"
  # every package the three need, libc included: the guest has nothing
  mapfile -t want < <(apt-get "${APTO[@]}" install --print-uris -qq --no-install-recommends "${PKGS[@]}" 2>/dev/null |
    awk '/^\x27/ { print $2 }')
  [[ ${#want[@]} -gt 0 ]] || skip "cannot resolve libcamera0.0.3 libcamera-ipa libcamera-dev in Debian's arm64 lists"
  names=()
  for f in "${want[@]}"; do
    [[ -f $DEBS/$f || -f $DEBS/${f//%3a/:} ]] || names+=("${f%%_*}=$(echo "$f" | cut -d_ -f2 | sed 's/%3a/:/')")
  done
  if [[ ${#names[@]} -gt 0 ]]; then
    echo "downloading ${#names[@]} arm64 packages"
    (cd "$DEBS" && retry apt-get "${APTO[@]}" download -qq "${names[@]}") ||
      skip "cannot download libcamera's arm64 packages (apt-get download failed)"
  fi
  rm -rf "$SYS" && mkdir -p "$SYS"
  for f in "$DEBS"/*.deb; do dpkg-deb -x "$f" "$SYS" || exit 1; done
  touch "$SYS/.done"
fi
LCSO=$(ls "$SYS"/usr/lib/$ML/libcamera.so.0.0.* 2>/dev/null | head -n 1)
[[ -n $LCSO ]] || { echo "no libcamera.so in the unpacked packages"; exit 1; }

# ---- 3. lc_capture, cross-built with the backend -------------------------
LC_SRC=("$ROOT/port/camera/libcamera" "$ROOT/port/include" "$ROOT/port/camera/camera_common.c"
        "$ROOT/port/clock/clock_posix.c" "$ROOT/lib/include" "$HW/guest/lc_capture.c" "${BASH_SOURCE[0]}")
if [[ -x $LR/bin/lc_capture && -f $LR/lib/$ML/libudev.so.1 &&
      -z $(find "${LC_SRC[@]}" "$SYS/.done" -newer "$LR/bin/lc_capture" 2>/dev/null | head -n 1) ]]; then
  echo "lc_capture and the overlay are up to date"
  exit 0
fi
rm -rf "$LR" && mkdir -p "$LR/bin" "$LR/lib/$ML" "$OUT/obj"
CF=(-O2 -Wall -Wextra -I"$ROOT/port/include" -I"$ROOT/lib/include")
echo "cross-compiling lc_capture (aarch64, libcamera $(basename "$LCSO"))"
aarch64-linux-gnu-g++ -std=c++17 "${CF[@]}" -I"$SYS/usr/include/libcamera" \
  -c "$ROOT/port/camera/libcamera/camera_libcamera.cpp" -o "$OUT/obj/camera_libcamera.o" || exit 1
for c in port/camera/libcamera/lc_format.c port/camera/libcamera/lc_pair.c \
         port/camera/camera_common.c port/clock/clock_posix.c \
         tests/hw/guest/lc_capture.c; do
  aarch64-linux-gnu-gcc -std=c99 "${CF[@]}" -c "$ROOT/$c" -o "$OUT/obj/$(basename "$c" .c).o" || exit 1
done
aarch64-linux-gnu-g++ -o "$LR/bin/lc_capture" "$OUT"/obj/*.o \
  -L"$SYS/usr/lib/$ML" -lcamera -lcamera-base -lpthread \
  -Wl,-rpath-link,"$SYS/usr/lib/$ML:$SYS/lib/$ML" || exit 1

# ---- 4. the guest overlay: IPA, proxy, libraries (NEEDED closure) -------
IPA_SO=$SYS/usr/lib/$ML/libcamera/ipa_vimc.so
PROXY=$SYS/usr/lib/$ML/libcamera/vimc_ipa_proxy   # Debian's IPA_PROXY_DIR
[[ -f $IPA_SO ]] || { echo "no ipa_vimc.so in libcamera-ipa"; exit 1; }
mkdir -p "$LR/usr/lib/$ML/libcamera" "$LR/usr/share/libcamera/ipa"
cp "$IPA_SO"* "$LR/usr/lib/$ML/libcamera/"
[[ -f $PROXY ]] && cp "$PROXY" "$LR/usr/lib/$ML/libcamera/"
[[ -d $SYS/usr/share/libcamera/ipa/vimc ]] && cp -r "$SYS/usr/share/libcamera/ipa/vimc" "$LR/usr/share/libcamera/ipa/"

# stub libudev.so.1: the udev_* symbols libcamera imports, with their
# version nodes, all returning 0/NULL (udev_new() == NULL -> sysfs)
STUB=$OUT/udev-stub
mkdir -p "$STUB"
aarch64-linux-gnu-readelf --dyn-syms -W "$LCSO" |
  awk '$7 == "UND" && $8 ~ /^udev_/ { split($8, a, "@"); print a[1], a[2] }' | sort -u > "$STUB/syms"
[[ -s $STUB/syms ]] || { echo "libcamera imports no udev_* symbols?"; exit 1; }
{
  echo "/* generated by tests/hw/build_libcamera.sh: udev_new() fails, so"
  echo " * libcamera uses its sysfs enumerator (no udev daemon in the guest) */"
  awk '{ print "void *" $1 "(void);\nvoid *" $1 "(void) { return 0; }" }' "$STUB/syms"
} > "$STUB/udev_stub.c"
awk '{ v = ($2 == "" ? "LIBUDEV_183" : $2); s[v] = s[v] "    " $1 ";\n" }
     END { for (v in s) printf "%s {\n  global:\n%s};\n", v, s[v] }' "$STUB/syms" > "$STUB/udev.map"
sed -i '$ s/};/  local: *;\n};/' "$STUB/udev.map"
aarch64-linux-gnu-gcc -shared -fPIC -O2 -o "$LR/lib/$ML/libudev.so.1" -Wl,-soname,libudev.so.1 \
  -Wl,--version-script,"$STUB/udev.map" "$STUB/udev_stub.c" || exit 1

resolve() {
  local d
  for d in lib/$ML usr/lib/$ML; do
    [[ -e $SYS/$d/$1 ]] && { echo "$SYS/$d/$1"; return 0; }
  done
  return 1
}
declare -A seen=([libudev.so.1]=1)
queue=("$LR/bin/lc_capture" "$IPA_SO")
[[ -f $PROXY ]] && queue+=("$PROXY")
while [[ ${#queue[@]} -gt 0 ]]; do
  f=${queue[0]}; queue=("${queue[@]:1}")
  for n in $(aarch64-linux-gnu-readelf -d "$f" | sed -n 's/.*Shared library: \[\(.*\)\]/\1/p'); do
    [[ -n ${seen[$n]:-} ]] && continue
    seen[$n]=1
    p=$(resolve "$n") || { echo "shared library $n (needed by $(basename "$f")) not in the packages"; exit 1; }
    cp -L "$p" "$LR/lib/$ML/$n"
    queue+=("$p")
  done
done
[[ -f $LR/lib/$ML/ld-linux-aarch64.so.1 ]] || cp -L "$(resolve ld-linux-aarch64.so.1)" "$LR/lib/$ML/"
ln -sf "$ML/ld-linux-aarch64.so.1" "$LR/lib/ld-linux-aarch64.so.1"
aarch64-linux-gnu-strip --strip-unneeded "$LR/bin/lc_capture" 2> /dev/null || true
echo "libcamera overlay: $(du -sk "$LR" | cut -f1) KiB, $(ls "$LR/lib/$ML" | wc -l) libraries"
