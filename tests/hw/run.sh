#!/usr/bin/env bash
# Emulated-hardware tests (issue 5): Debian's arm64 kernel under
# qemu-system-aarch64 -M virt (TCG) with a small initramfs, exercising the
# real kernel interfaces negobs_run uses:
#   vivid  V4L2 capture of an injected stereo pair (vivid loopback)
#   gpio   GPIO character device on PL061 (+ gpio-sim when it builds)
#   pwm    PWM sysfs ABI on pwm-sim.ko (tests/hw/kmod/pwm-sim.c)
#   run-curb         the real negobs_run (static aarch64, built from this
#                    tree) on a synthetic walk toward a curb; motor line
#                    (gpio-sim) observed from outside
#   run-curb-pwm     run-curb with --alert pwm: on pwm-sim, observed
#                    through the channel's sysfs duty_cycle
#   run-camera-loss  the real negobs_run: right camera stops, no-info
#                    pattern on the line, frames return, verdicts resume
#   run-fault-frozen / -drift / -gpio / -pwm  the real negobs_run under the
#                    other runtime faults of issue 6 (frozen stream, left/
#                    right drift beyond pair_tolerance_ms, motor GPIO chip
#                    gone, PWM writes failing): logged, no-info on the
#                    line, recovered without a restart
#   run-fmt-sbs / -y16 / -y10  the real negobs_run on a side-by-side
#                    1280x720 GREY camera (one node), on Y16 and on Y10
#                    cameras: recorded pairs = the original frames after
#                    split, crop and 2x2 binning, pixel for pixel
#   run-button       the real negobs_run's push button on a gpio-sim input
#                    (pull set through sysfs): short press -> preset, long
#                    press -> pause / resume, each confirmed on the motor
#   libcamera-vimc   one vimc camera through negobs' libcamera backend
#                    (Debian's arm64 libcamera 0.0.3, lc_capture)
#   payload  /payload/run.sh from --payload DIR (drop-in for negobs_run)
#
# usage: bash tests/hw/run.sh [--sections vivid,gpio,pwm,run-curb,run-camera-loss,run-curb-pwm,run-fault-frozen,...[,payload]]
#          [--payload DIR] [--payload-file FILE]... [--no-gpio-sim]
#          [--timeout S] [--clean]
# --payload DIR / --payload-file FILE (repeatable) copy into the guest's
# /payload and add the "payload" section, which runs /payload/run.sh
# (tests/hw/payload/run.sh unless DIR has one): e.g.
#   bash tests/hw/run.sh --payload-file build/aarch64-static/firmware_app/negobs_run
#
# Work files (downloaded .debs, unpacked kernel and headers, built modules,
# guest binaries, initramfs, serial log) go to build/hw (or $NEGOBS_HW_WORK)
# and are reused on reruns.  Nothing is installed into /boot or /lib/modules:
# kernel, headers and kbuild packages are fetched with `apt-get download`
# through a private apt configuration and unpacked with dpkg-deb -x.
# Host tools (qemu-system-arm, the aarch64 cross compiler, cpio, kmod) are
# installed with apt-get when missing and running as root.
#
# Output: one "SECTION <name>: PASS|FAIL|SKIPPED: <reason>" line per
# section, then "N passed, N failed, N skipped".  Exit 1 if any section
# failed, else 0 (skips included).  Details: docs/EMULATION_TESTS.md.
set -u -o pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
HW=$ROOT/tests/hw
WORK=${NEGOBS_HW_WORK:-$ROOT/build/hw}
SECTIONS="vivid gpio pwm run-curb run-camera-loss run-curb-pwm run-fault-frozen run-fault-drift run-fault-gpio run-fault-pwm run-fmt-sbs run-fmt-y16 run-fmt-y10 run-button libcamera-vimc"
PAYLOAD=""
PAYLOAD_FILES=()
GPIO_SIM=1
QEMU_TIMEOUT=720
T0=$(date +%s.%N)

while [[ $# -gt 0 ]]; do
  case "$1" in
    --sections) SECTIONS=${2//,/ }; shift 2 ;;
    --payload) PAYLOAD=$(cd "$2" && pwd) || exit 2; shift 2 ;;
    --payload-file) [[ -f $2 ]] || { echo "no such file: $2" >&2; exit 2; }
                    PAYLOAD_FILES+=("$(cd "$(dirname "$2")" && pwd)/$(basename "$2")"); shift 2 ;;
    --no-gpio-sim) GPIO_SIM=0; shift ;;
    --timeout) QEMU_TIMEOUT=$2; shift 2 ;;
    --clean) rm -rf "$WORK"; shift ;;
    -h|--help) sed -n '2,/^set -u/p' "${BASH_SOURCE[0]}" | sed '$d'; exit 0 ;;
    *) echo "unknown argument: $1" >&2; exit 2 ;;
  esac
done
if [[ -n $PAYLOAD || ${#PAYLOAD_FILES[@]} -gt 0 ]] && [[ " $SECTIONS " != *" payload "* ]]; then
  SECTIONS="$SECTIONS payload"
fi

mkdir -p "$WORK"
LOG=$WORK/run.log
: > "$LOG"

elapsed() { awk -v a="$T0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }'; }
step() { echo "hw: [$(elapsed)s] $*"; }

declare -A RESULT=() REASON=()
# Marks every section not decided yet as skipped, prints the summary, exits 0.
skip_all() {
  local s
  for s in $SECTIONS; do
    [[ -n ${RESULT[$s]:-} ]] && continue
    RESULT[$s]=SKIPPED; REASON[$s]=$1
  done
  summary
}
summary() {
  local s p=0 f=0 k=0
  for s in $SECTIONS; do
    case ${RESULT[$s]:-FAIL} in
      PASS) p=$((p + 1)); echo "SECTION $s: PASS${REASON[$s]:+ ${REASON[$s]}}" ;;
      SKIPPED) k=$((k + 1)); echo "SECTION $s: SKIPPED: ${REASON[$s]:-}" ;;
      *) f=$((f + 1)); echo "SECTION $s: FAIL${REASON[$s]:+ ${REASON[$s]}}" ;;
    esac
  done
  step "done (work folder $WORK, serial log $WORK/guest.log)"
  echo "$p passed, $f failed, $k skipped"
  [[ $f -eq 0 ]] && exit 0 || exit 1
}
# quiet: runs a command with its output into the log; shows the tail on error
quiet() {
  if ! "$@" >> "$LOG" 2>&1; then
    echo "hw: command failed: $*" >&2
    tail -n 15 "$LOG" | sed 's/^/hw:   /' >&2
    return 1
  fi
}

# ---- host tools ------------------------------------------------------------
need_tools() {
  local missing=() t
  for t in qemu-system-aarch64:qemu-system-arm aarch64-linux-gnu-gcc:gcc-aarch64-linux-gnu \
           aarch64-linux-gnu-gcc-12:gcc-12-aarch64-linux-gnu cpio:cpio depmod:kmod \
           aarch64-linux-gnu-g++:g++-aarch64-linux-gnu \
           modprobe:kmod xz:xz-utils make:make gzip:gzip dpkg-deb:dpkg apt-get:apt; do
    command -v "${t%%:*}" > /dev/null 2>&1 || missing+=("${t#*:}")
  done
  [[ -f /usr/aarch64-linux-gnu/lib/libc.a ]] || missing+=(libc6-dev-arm64-cross)
  # linux-kbuild-6.1's tools (modpost, fixdep) need these host libraries
  [[ -e /usr/lib/x86_64-linux-gnu/libelf.so.1 || $(uname -m) != x86_64 ]] || missing+=(libelf1)
  [[ -e /usr/lib/x86_64-linux-gnu/libssl.so.3 || $(uname -m) != x86_64 ]] || missing+=(libssl3)
  [[ ${#missing[@]} -eq 0 ]] && return 0
  mapfile -t missing < <(printf '%s\n' "${missing[@]}" | sort -u)
  if [[ $(id -u) -ne 0 ]]; then
    echo "hw: missing host packages and not root: ${missing[*]}"
    return 1
  fi
  step "apt-get install ${missing[*]}"
  # A mirror mid-sync fails one index ("Hashes of expected file") while
  # the others, and the lists of an earlier update, still serve the
  # packages: try the install with them; it fails by itself if they do not.
  apt_retry apt-get update -qq ||
    step "apt-get update failed; installing from the lists at hand"
  quiet env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    "${missing[@]}"
}
# retries apt: a mirror mid-sync ("File has unexpected size") heals in minutes
apt_retry() {
  local i
  for i in 1 2 3 4 5; do
    "$@" >> "$LOG" 2>&1 && return 0
    step "apt failed (try $i/5): $*"
    [[ $i -lt 5 ]] && sleep $((i * 2))
  done
  tail -n 5 "$LOG" | sed 's/^/hw:   /'
  return 1
}

# ---- arm64 packages through a private apt configuration --------------------
# (no dpkg --add-architecture, the host's dpkg database is untouched)
APTD=$WORK/apt-arm64
APTO=(-o APT::Architecture=arm64 -o APT::Architectures=arm64
      -o Dir::Etc::sourcelist="$APTD/sources.list" -o Dir::Etc::sourceparts="$APTD/parts"
      -o Dir::State::Lists="$APTD/lists" -o Dir::Cache="$APTD/cache"
      -o Dir::State::status="$APTD/status" -o Debug::NoLocking=1)
apt_arm64_setup() {
  mkdir -p "$APTD/lists/partial" "$APTD/cache/archives/partial" "$APTD/parts"
  [[ -f $APTD/status ]] || : > "$APTD/status"
  local k=/usr/share/keyrings/debian-archive-keyring.gpg
  [[ -f $k ]] || { echo "hw: $k missing (debian-archive-keyring)"; return 1; }
  {
    echo "deb [signed-by=$k] http://deb.debian.org/debian bookworm main"
    echo "deb [signed-by=$k] http://deb.debian.org/debian bookworm-updates main"
    echo "deb [signed-by=$k] http://deb.debian.org/debian-security bookworm-security main"
  } > "$APTD/sources.list"
  # refresh the lists at most every 6 hours
  if [[ -z $(find "$APTD/lists" -maxdepth 1 -name '*_Packages*' -mmin -360 2>/dev/null | head -n 1) ]]; then
    step "apt-get update (arm64, private lists)"
    # apt-get update exits 0 when some sources failed: count the indexes
    if ! apt_retry arm64_update; then
      # older lists still name packages that may be cached in debs/
      compgen -G "$APTD/lists/*_Packages*" > /dev/null || return 1
      step "apt-get update failed; going on with the lists from an earlier run"
    fi
  fi
}
arm64_update() {
  local out rc=0
  out=$(apt-get "${APTO[@]}" update -q 2>&1) || rc=1
  echo "$out"
  if grep -qE '^(Err:|E: |W: (Failed to fetch|Some index files failed))' <<< "$out"; then rc=1; fi
  compgen -G "$APTD/lists/*_Packages*" > /dev/null || rc=1
  return $rc
}
# dl DEST PKG[=VER]...: apt-get download into DEST unless a matching .deb is there
dl() {
  local dest=$1; shift
  local p name ver
  mkdir -p "$dest"
  for p in "$@"; do
    name=${p%%=*}; ver=${p#*=}; [[ $ver == "$p" ]] && ver=""
    if compgen -G "$dest/${name}_${ver:+${ver//:/%3a}}*.deb" > /dev/null; then continue; fi
    rm -f "$dest/${name}_"*.deb
    (cd "$dest" && apt_retry apt-get "${APTO[@]}" download -qq "$p") || return 1
  done
}

# ---- main flow ---------------------------------------------------------------
step "sections: $SECTIONS; work folder $WORK"
need_tools || skip_all "host tools missing (qemu-system-arm, gcc-aarch64-linux-gnu, cpio, kmod; run as root to install)"
apt_arm64_setup || skip_all "cannot reach Debian's arm64 package lists (apt-get update failed)"

KABI=$(apt-cache "${APTO[@]}" depends linux-image-arm64 2>/dev/null |
       sed -n 's/.*Depends: linux-image-\([0-9].*\)-arm64$/\1/p' | head -n 1)
[[ -n $KABI ]] || skip_all "cannot resolve the arm64 kernel ABI from linux-image-arm64"
KVER=$KABI-arm64
KPKGVER=$(apt-cache "${APTO[@]}" policy "linux-image-$KVER" | sed -n 's/^ *Candidate: //p')
[[ -n $KPKGVER && $KPKGVER != "(none)" ]] || skip_all "no candidate for linux-image-$KVER"
step "kernel $KVER, package version $KPKGVER"

DEBS=$WORK/debs
dl "$DEBS" "linux-image-$KVER=$KPKGVER" busybox-static ||
  skip_all "cannot download linux-image-$KVER / busybox-static (arm64)"

# unpacked kernel + busybox, redone when the version changes
KROOT=$WORK/kernel
if [[ $(cat "$KROOT/.version" 2>/dev/null) != "$KVER $KPKGVER" ]]; then
  step "unpacking linux-image-$KVER"
  rm -rf "$KROOT" && mkdir -p "$KROOT"
  dpkg-deb -x "$DEBS/linux-image-${KVER}_${KPKGVER}_arm64.deb" "$KROOT" ||
    skip_all "cannot unpack linux-image-$KVER"
  echo "$KVER $KPKGVER" > "$KROOT/.version"
fi
BB=$WORK/busybox
if [[ ! -x $BB/bin/busybox ]]; then
  rm -rf "$BB"; dpkg-deb -x "$DEBS"/busybox-static_*_arm64.deb "$BB" ||
    skip_all "cannot unpack busybox-static (arm64)"
fi
KIMG=$KROOT/boot/vmlinuz-$KVER
[[ -f $KIMG ]] || skip_all "no $KIMG in the kernel package"

# ---- out-of-tree modules (pwm-sim; gpio-sim + irqsim from linux-source) ----
# Headers: linux-headers-$KVER (arm64) + -common + linux-kbuild-6.1 (host
# arch: modpost/fixdep run here), all unpacked into one tree so its relative
# scripts/tools links resolve, and its Makefile pointed at the unpacked
# -common.  Built with the Debian kernel's own compiler name
# (aarch64-linux-gnu-gcc-12); vermagic matches the kernel.
KMOD_OK=0 GPIOSIM_OK=0
HDR=$WORK/headers
HOSTARCH=$(dpkg --print-architecture)
KBUILD_SER=6.1
build_kmods() {
  if [[ $(cat "$HDR/.version" 2>/dev/null) != "$KVER $KPKGVER" ]]; then
    step "fetching linux-headers-$KVER + linux-kbuild-$KBUILD_SER"
    dl "$DEBS" "linux-headers-$KVER=$KPKGVER" "linux-headers-$KABI-common=$KPKGVER" || return 1
    # linux-kbuild is a host-architecture package: the host's own apt
    (cd "$DEBS" && compgen -G "linux-kbuild-${KBUILD_SER}_${KPKGVER}_$HOSTARCH.deb" > /dev/null ||
       { rm -f linux-kbuild-*.deb; apt_retry apt-get download -qq "linux-kbuild-$KBUILD_SER=$KPKGVER" ||
         { apt_retry apt-get update -qq && apt_retry apt-get download -qq "linux-kbuild-$KBUILD_SER=$KPKGVER"; }; }) ||
      return 1
    rm -rf "$HDR" && mkdir -p "$HDR"
    local f
    for f in "$DEBS/linux-headers-${KVER}_${KPKGVER}_arm64.deb" \
             "$DEBS/linux-headers-$KABI-common_${KPKGVER}_all.deb" \
             "$DEBS/linux-kbuild-${KBUILD_SER}_${KPKGVER}_$HOSTARCH.deb"; do
      dpkg-deb -x "$f" "$HDR" || return 1
    done
    sed -i "s|^include /usr/src/|include $HDR/usr/src/|" "$HDR/usr/src/linux-headers-$KVER/Makefile"
    echo "$KVER $KPKGVER" > "$HDR/.version"
  fi
  local kb=(make -s -C "$HDR/usr/src/linux-headers-$KVER" DEB_BUILD_ARCH="$HOSTARCH"
            DEB_HOST_ARCH=arm64 DEB_HOST_GNU_TYPE=aarch64-linux-gnu)
  local KM=$WORK/kmod
  mkdir -p "$KM/pwm-sim"
  if ! cmp -s "$HW/kmod/pwm-sim.c" "$KM/pwm-sim/pwm-sim.c" || [[ ! -f $KM/pwm-sim/pwm-sim.ko ]] ||
     [[ $(cat "$KM/.version" 2>/dev/null) != "$KVER $KPKGVER" ]]; then
    step "building pwm-sim.ko"
    rm -rf "$KM/pwm-sim" && mkdir -p "$KM/pwm-sim"
    cp "$HW/kmod/pwm-sim.c" "$HW/kmod/Kbuild" "$KM/pwm-sim/"
    quiet "${kb[@]}" M="$KM/pwm-sim" modules || return 1
  fi
  KMOD_OK=1
  if [[ $GPIO_SIM = 1 ]]; then
    if [[ ! -f $KM/gpio-sim/gpio-sim.ko || $(cat "$KM/.version" 2>/dev/null) != "$KVER $KPKGVER" ]]; then
      step "fetching linux-source-$KBUILD_SER for gpio-sim + irq_sim"
      dl "$DEBS" "linux-source-$KBUILD_SER=$KPKGVER" || return 1
      rm -rf "$KM/gpio-sim" "$WORK/src" && mkdir -p "$KM/gpio-sim" "$WORK/src"
      local L=linux-source-$KBUILD_SER
      dpkg-deb --fsys-tarfile "$DEBS/${L}_${KPKGVER}_all.deb" |
        tar -xO "./usr/src/$L.tar.xz" |
        tar -xJ -C "$WORK/src" "$L/drivers/gpio/gpio-sim.c" "$L/drivers/gpio/gpiolib.h" \
          "$L/kernel/irq/irq_sim.c" || return 1
      cp "$WORK/src/$L/drivers/gpio/gpio-sim.c" "$WORK/src/$L/drivers/gpio/gpiolib.h" "$KM/gpio-sim/"
      # CONFIG_IRQ_SIM is off in Debian's kernels: irq_sim.c as its own
      # module; irq_to_desc() is not exported, generic_handle_irq() runs the
      # same handle_simple_irq.
      sed 's/handle_simple_irq(irq_to_desc(\([a-z_]*\)))/generic_handle_irq(\1)/' \
        "$WORK/src/$L/kernel/irq/irq_sim.c" > "$KM/gpio-sim/irqsim.c"
      grep -q 'generic_handle_irq' "$KM/gpio-sim/irqsim.c" || { echo "hw: irq_sim.c patch did not apply"; return 1; }
      printf '\n#include <linux/module.h>\nMODULE_LICENSE("GPL");\n' >> "$KM/gpio-sim/irqsim.c"
      echo 'obj-m := irqsim.o gpio-sim.o' > "$KM/gpio-sim/Kbuild"
      step "building irqsim.ko + gpio-sim.ko"
      quiet "${kb[@]}" M="$KM/gpio-sim" modules || { rm -f "$KM/gpio-sim/gpio-sim.ko"; return 1; }
    fi
    GPIOSIM_OK=1
  fi
  echo "$KVER $KPKGVER" > "$KM/.version"
}
build_kmods || step "module build incomplete (log: $LOG)"

# ---- guest programs (static aarch64) -------------------------------------------
GB=$WORK/guest-bin
mkdir -p "$GB"
GUEST_OK=1
for p in v4l2_loop gpio_test pwm_test motor_watch; do
  if [[ ! -x $GB/$p || $HW/guest/$p.c -nt $GB/$p ]]; then
    step "cross-compiling $p (static aarch64)"
    quiet aarch64-linux-gnu-gcc -std=c99 -O2 -Wall -Wextra -static -o "$GB/$p" "$HW/guest/$p.c" ||
      { GUEST_OK=0; rm -f "$GB/$p"; }
  fi
done
[[ $GUEST_OK = 1 ]] || skip_all "cross-compiling the guest programs failed (log: $LOG)"

# ---- the real negobs_run + its scenes (run-curb, run-camera-loss) ----------------
NEGOBS_OK=0 NEGOBS_WHY=""
if [[ " $SECTIONS " == *" run-"* ]]; then
  step "building negobs_run (static aarch64) + synth scenes (tests/hw/build_negobs.sh)"
  bash "$HW/build_negobs.sh" "$WORK/negobs" >> "$LOG" 2>&1
  case $? in
    0) NEGOBS_OK=1 ;;
    77) NEGOBS_WHY=$(tail -n 1 "$LOG") ;;
    *) NEGOBS_WHY="tests/hw/build_negobs.sh failed (log: $LOG)"; tail -n 15 "$LOG" | sed 's/^/hw:   /' ;;
  esac
fi

# ---- libcamera-vimc: vimc.ko, lc_capture + Debian's arm64 libcamera -----------
LC_OK=0 LC_WHY=""
if [[ " $SECTIONS " == *" libcamera-vimc "* ]]; then
  step "building vimc.ko + lc_capture against arm64 libcamera (tests/hw/build_libcamera.sh)"
  bash "$HW/build_libcamera.sh" "$WORK" "$KVER" "$KPKGVER" >> "$LOG" 2>&1
  case $? in
    0) LC_OK=1 ;;
    77) LC_WHY=$(tail -n 1 "$LOG") ;;
    *) LC_WHY="tests/hw/build_libcamera.sh failed (log: $LOG)"; tail -n 15 "$LOG" | sed 's/^/hw:   /' ;;
  esac
fi

# decide which sections can run; the others are skipped with a reason
RUN=""
for s in $SECTIONS; do
  case $s in
    pwm) [[ $KMOD_OK = 1 ]] || { RESULT[$s]=SKIPPED; REASON[$s]="pwm-sim.ko could not be built (log: $LOG)"; continue; } ;;
    vivid|gpio|payload) ;;
    libcamera-vimc)
      if [[ $LC_OK != 1 ]]; then
        if [[ $LC_WHY == *build_libcamera.sh\ failed* ]]; then RESULT[$s]=FAIL; REASON[$s]="($LC_WHY)"
        else RESULT[$s]=SKIPPED; REASON[$s]="libcamera/vimc not available: $LC_WHY"; fi
        continue
      fi ;;
    run-curb|run-camera-loss|run-curb-pwm|run-fault-frozen|run-fault-drift|run-fault-gpio|run-fault-pwm|run-fmt-sbs|run-fmt-y16|run-fmt-y10|run-button)
      if [[ ($s == run-curb-pwm || $s == run-fault-pwm) && $KMOD_OK != 1 ]]; then
        RESULT[$s]=SKIPPED; REASON[$s]="pwm-sim.ko could not be built (log: $LOG)"; continue
      fi
      if [[ $NEGOBS_OK != 1 ]]; then
        # a failed build is a failure, a missing prerequisite a skip
        if [[ $NEGOBS_WHY == *build_negobs.sh\ failed* ]]; then RESULT[$s]=FAIL; REASON[$s]="($NEGOBS_WHY)"
        else RESULT[$s]=SKIPPED; REASON[$s]="negobs_run/negobs_synth not buildable: $NEGOBS_WHY"; fi
        continue
      fi
      [[ $GPIOSIM_OK = 1 || $s == run-curb-pwm || $s == run-fault-pwm || $s == run-fmt-* ]] || { RESULT[$s]=SKIPPED; REASON[$s]="gpio-sim.ko not built (--no-gpio-sim or build failure): no outside motor observer"; continue; } ;;
    *) RESULT[$s]=FAIL; REASON[$s]="(unknown section)"; continue ;;
  esac
  RUN="$RUN $s"
done
RUN=${RUN# }
[[ -n $RUN ]] || summary

# ---- initramfs ---------------------------------------------------------------------
# busybox as /bin, the modules the sections need plus their dependencies
# (resolved with modprobe --show-depends, depmod run on the image), the test
# scripts and programs, and the payload directory as /payload.
step "building the initramfs"
MODROOT=$KROOT/lib/modules/$KVER
mkdir -p "$MODROOT/extra"
rm -f "$MODROOT/extra/"*.ko
[[ $KMOD_OK = 1 ]] && cp "$WORK/kmod/pwm-sim/pwm-sim.ko" "$MODROOT/extra/"
[[ $GPIOSIM_OK = 1 ]] && cp "$WORK/kmod/gpio-sim/"{irqsim,gpio-sim}.ko "$MODROOT/extra/"
[[ $LC_OK = 1 ]] && cp "$WORK/libcamera/vimc.ko" "$MODROOT/extra/"
depmod -b "$KROOT" "$KVER" || skip_all "depmod on the unpacked kernel failed"
IR=$WORK/initramfs
rm -rf "$IR"
mkdir -p "$IR"/{bin,sbin,proc,sys,dev,tmp,tests,payload,usr/bin,lib/modules/"$KVER"}
cp "$BB/bin/busybox" "$IR/bin/busybox"
cp "$HW/guest/init.sh" "$IR/init" && chmod 755 "$IR/init"
sed -i '1s|.*|#!/bin/busybox sh|' "$IR/init"
cp "$HW/guest/"{lib,vivid,gpio,pwm,payload,negobs_lib,run-curb,run-camera-loss,run-curb-pwm,run-button}.sh \
  "$HW/guest/"run-fault-*.sh "$HW/guest/"run-fmt-*.sh "$IR/tests/"
if [[ " $RUN " == *" run-"* ]]; then
  mkdir -p "$IR/negobs/curb" "$IR/negobs/flat"
  cp "$WORK/negobs/"{negobs_run,rig.conf} "$IR/negobs/"
  cp "$WORK/negobs/curb/"*.{raw,md5} "$IR/negobs/curb/"
  cp "$WORK/negobs/flat/"*.{raw,md5} "$IR/negobs/flat/"
  if [[ " $RUN " == *" run-fmt-"* ]]; then
    mkdir -p "$IR/negobs/fmt"
    cp "$WORK/negobs/fmt/"*.{raw,md5} "$IR/negobs/fmt/"
  fi
fi
cp "$GB/"* "$IR/bin/"
cp "$HW/guest/libcamera-vimc.sh" "$IR/tests/"
# lc_capture, its libraries (/lib/aarch64-linux-gnu) and the vimc IPA
[[ $LC_OK = 1 && " $RUN " == *" libcamera-vimc "* ]] && cp -a "$WORK/libcamera/root/." "$IR/"
MODS=(vivid configfs)
[[ $KMOD_OK = 1 ]] && MODS+=(pwm-sim)
[[ $GPIOSIM_OK = 1 ]] && MODS+=(gpio-sim)
[[ $LC_OK = 1 ]] && MODS+=(vimc)
for m in "${MODS[@]}"; do
  modprobe -d "$KROOT" -S "$KVER" --show-depends "$m" 2>>"$LOG" | awk '$1 == "insmod" { print $2 }'
done | sort -u | while read -r ko; do
  rel=${ko#"$KROOT"}
  mkdir -p "$IR$(dirname "$rel")"
  cp "$ko" "$IR$rel"
done
cp "$MODROOT"/modules.{order,builtin,builtin.modinfo} "$IR/lib/modules/$KVER/" 2>/dev/null
depmod -b "$IR" "$KVER" || skip_all "depmod on the initramfs failed"
# payload: the --payload directory, the --payload-file files, and the
# default tests/hw/payload/run.sh unless the directory brings its own
[[ -n $PAYLOAD ]] && cp -a "$PAYLOAD/." "$IR/payload/"
for f in "${PAYLOAD_FILES[@]}"; do cp -a "$f" "$IR/payload/"; done
[[ -f $IR/payload/run.sh ]] || cp "$HW/payload/run.sh" "$IR/payload/run.sh"
for f in "$IR"/payload/*; do
  [[ -f $f && -x $f ]] || continue
  if aarch64-linux-gnu-readelf -h "$f" > /dev/null 2>&1; then
    aarch64-linux-gnu-readelf -h "$f" | grep -q 'Machine:.*AArch64' ||
      step "warning: payload $(basename "$f") is not an AArch64 binary"
    aarch64-linux-gnu-readelf -l "$f" 2>/dev/null | grep -q 'Requesting program interpreter' &&
      step "warning: payload $(basename "$f") is dynamically linked; the guest has no libc (build it -static)"
  fi
done
(cd "$IR" && find . | cpio -o -H newc --quiet | gzip -1) > "$WORK/initramfs.cpio.gz" ||
  skip_all "cpio of the initramfs failed"
step "initramfs $(du -k "$WORK/initramfs.cpio.gz" | cut -f1) KiB ($(find "$IR/lib/modules" -name '*.ko' | wc -l) modules)"

# ---- boot ------------------------------------------------------------------------
GLOG=$WORK/guest.log
step "booting qemu-system-aarch64 -M virt (TCG), sections: $RUN (timeout ${QEMU_TIMEOUT}s)"
TB=$(date +%s.%N)
timeout --kill-after=10 "$QEMU_TIMEOUT" qemu-system-aarch64 -M virt -accel tcg -cpu cortex-a53 \
  -smp 2 -m 1024 -nographic -no-reboot -nic none \
  -kernel "$KIMG" -initrd "$WORK/initramfs.cpio.gz" \
  -append "console=ttyAMA0 panic=-1 quiet loglevel=4 negobs.sections=${RUN// /,}" \
  < /dev/null > "$GLOG" 2>&1
QRC=$?
BOOT_S=$(awk -v a="$TB" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
tr -d '\r' < "$GLOG" > "$GLOG.txt"
grep -E '^(\[[a-z-]+\] |GUEST|SECTION )' "$GLOG.txt" | sed 's/^/guest| /'
step "qemu exited with $QRC after ${BOOT_S}s"
[[ $QRC = 124 || $QRC = 137 ]] && step "qemu timed out after ${QEMU_TIMEOUT}s (serial log: $GLOG)"

for s in $RUN; do
  line=$(grep -E "^SECTION $s: " "$GLOG.txt" | tail -n 1)
  case $line in
    "SECTION $s: PASS"*) RESULT[$s]=PASS; REASON[$s]="" ;;
    "SECTION $s: SKIPPED:"*) RESULT[$s]=SKIPPED; REASON[$s]=${line#"SECTION $s: SKIPPED: "} ;;
    "SECTION $s: FAIL"*) RESULT[$s]=FAIL
      # the section's own first complaint, so that a CI log that keeps
      # only the SECTION lines still says what went wrong (init.sh prints
      # a section's lines as "[NAME] ..."; a killed section says so last)
      why=$(grep -m1 -E "^\[$s\] (.*FAIL: |section did not finish)" "$GLOG.txt" |
            sed -e "s/^\[$s\] //" -e "s/^$s: FAIL: //")
      REASON[$s]="(${why:+$why; }see $GLOG)" ;;
    *) RESULT[$s]=FAIL; REASON[$s]="(no result on the serial log; qemu rc $QRC, see $GLOG)" ;;
  esac
done
[[ $GPIOSIM_OK = 1 || " $RUN " != *" gpio "* ]] || step "note: gpio section ran on PL061 only (gpio-sim not built)"
summary
