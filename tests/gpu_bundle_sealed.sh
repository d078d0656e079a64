#!/usr/bin/env bash
# ctest gpu_bundle_sealed: the GPU bundle (scripts/gpu_bundle.sh) runs with nothing from
# the system but glibc. A bundle of this build tree goes into a root holding only glibc,
# lavapipe's ICD with its libraries (less the C++ runtime, which must then come from the
# bundle's fallback), and busybox (a static binary) for the shell and its tools; in a
# private mount namespace, chrooted there, `run.sh --quick` must pass every step.
# Exit 77 (ctest: skipped) with the reason where this machine cannot make such a root
# (not root, no mount namespaces, no static busybox, no lavapipe).
#
# usage: gpu_bundle_sealed.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 BUILD_DIR SOURCE_DIR" >&2; exit 2; }
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
skip() { echo "gpu_bundle_sealed: SKIPPED: $*"; exit 77; }

[ "$(id -u)" -eq 0 ] || skip "chroot and mount namespaces need root"
unshare --mount true 2>/dev/null || skip "this machine refuses a private mount namespace (unshare --mount)"
busybox=$(command -v busybox || true)
[ -n "$busybox" ] || skip "no busybox (scripts/setup.sh installs busybox-static)"
if ldd "$busybox" >/dev/null 2>&1; then skip "$busybox is dynamically linked (busybox-static has the static one)"; fi
icd=$(ls /usr/share/vulkan/icd.d/lvp_icd*.json 2>/dev/null | head -n1 || true)
[ -n "$icd" ] || skip "no lavapipe ICD in /usr/share/vulkan/icd.d"
lvp=$(sed -n 's/.*"library_path": *"\([^"]*\)".*/\1/p' "$icd")
case "$lvp" in /*) ;; *) lvp=/usr/lib/x86_64-linux-gnu/$lvp ;; esac # a bare name: the loader's search path
[ -e "$lvp" ] || skip "lavapipe's library $lvp (named by $icd) is missing"

work="$build/bundle-sealed"
rm -rf "$work"
mkdir -p "$work"
bash "$src/scripts/gpu_bundle.sh" --from-build "$build" --out "$work/bundle"

root="$work/root"
mkdir -p "$root"/usr/lib/x86_64-linux-gnu "$root"/usr/lib64 "$root"/usr/bin "$root"/usr/share/vulkan/icd.d \
  "$root"/dev "$root"/proc "$root"/tmp "$root"/out
ln -s usr/lib "$root/lib"
ln -s usr/lib64 "$root/lib64"
ln -s usr/bin "$root/bin"
# glibc: the libc6 package's libraries and its dynamic loader, links kept.
dpkg -L libc6 | grep -E '^(/usr)?/lib(64)?/.*\.so' | while read -r f; do
  rel=${f#/}
  rel=${rel#usr/}
  mkdir -p "$root/usr/$(dirname "$rel")"
  cp -a "$f" "$root/usr/$rel"
done
# lavapipe and its libraries, but neither glibc's (above) nor the C++ runtime's.
cp "$icd" "$root/usr/share/vulkan/icd.d/"
cp -L "$lvp" "$root/usr/lib/x86_64-linux-gnu/$(basename "$lvp")"
ldd "$lvp" | awk '$2 == "=>" && $3 ~ /^\// { print $1, $3 }' | while read -r name path; do
  case "$name" in
    libc.so*|libm.so*|libpthread.so*|libdl.so*|librt.so*|libresolv.so*|ld-linux*) continue ;;
    libstdc++.so*|libgcc_s.so*) continue ;;
  esac
  cp -L "$path" "$root/usr/lib/x86_64-linux-gnu/$name"
done
# busybox: the shell and every tool run.sh uses.
cp "$busybox" "$root/usr/bin/busybox"
for applet in sh cat sed grep awk tr mkdir date tee cp sleep uname env head tail ls rm nproc dirname wc sort cut timeout true; do
  ln -sf busybox "$root/usr/bin/$applet"
done
cp -al "$work/bundle/masq-gpu" "$root/masq-gpu" 2>/dev/null || cp -a "$work/bundle/masq-gpu" "$root/masq-gpu"
if [ -e "$root/usr/lib/x86_64-linux-gnu/libstdc++.so.6" ]; then
  echo "gpu_bundle_sealed: the root holds a system libstdc++: the fallback would go untested" >&2
  exit 1
fi
echo "gpu_bundle_sealed: root $(du -sh "$root" | cut -f1): glibc, $(basename "$lvp") and $(ls "$root/usr/lib/x86_64-linux-gnu" | wc -l) libraries, busybox, the bundle"

set +e
env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/tmp MESA_SHADER_CACHE_DISABLE=true LP_NUM_THREADS="${LP_NUM_THREADS:-2}" \
  unshare --mount --fork /bin/sh -c "mount --bind /dev '$root/dev' && mount -t proc proc '$root/proc' &&
    exec chroot '$root' /usr/bin/sh /masq-gpu/run.sh --quick /out"
rc=$?
set -e
cp "$root/out/RESULTS.md" "$root/out/log.txt" "$work/" 2>/dev/null || true
echo "---- RESULTS.md"
cat "$work/RESULTS.md" 2>/dev/null || echo "(none written)"
if [ $rc -ne 0 ]; then
  echo "---- the end of log.txt"
  tail -n 40 "$work/log.txt" 2>/dev/null || true
  echo "gpu_bundle_sealed: run.sh --quick exited $rc in the sealed root" >&2
  exit 1
fi
grep -q "Every step passed" "$work/RESULTS.md" || { echo "gpu_bundle_sealed: RESULTS.md does not say every step passed" >&2; exit 1; }
grep -q "the bundle's (lib/fallback" "$work/RESULTS.md" ||
  { echo "gpu_bundle_sealed: run.sh did not take the bundle's C++ runtime in a root without one" >&2; exit 1; }
rm -rf "$root" "$work/bundle" # hundreds of MiB of libraries (this build links OpenImageIO)
echo "gpu_bundle_sealed: passed"
