#!/bin/sh
# ctest package_deb: builds the .deb with CPack (cmake/package.cmake), lists
# its contents and control data, checks that the library, headers, CMake
# package, pkg-config file, tools and Python module are in it under /usr, and
# runs the unpacked copy (dpkg-deb -x, no root needed): svo_info --version,
# and `import voxkit` finding libvoxkit beside it through its RPATH.
# Usage: test_package.sh BUILD_DIR WORK_DIR CPACK PYTHON3
set -eu
BUILD=$1 WORK=$2 CPACK=$3 PY=${4:-}
rm -rf "$WORK"
mkdir -p "$WORK"
"$CPACK" -G DEB --config "$BUILD/CPackConfig.cmake" -B "$WORK" >"$WORK/cpack.log" 2>&1 || { cat "$WORK/cpack.log"; exit 1; }
DEB=$(ls "$WORK"/*.deb)
echo "built $(basename "$DEB") ($(wc -c <"$DEB" | tr -d ' ') bytes)"
dpkg-deb -I "$DEB" | sed -n 's/^ \(Package\|Version\|Architecture\|Depends\|Installed-Size\):/  \1:/p'
dpkg-deb -c "$DEB" | awk '{ print "  " $6 ($7 ? " " $7 " " $8 : "") }' | tee "$WORK/contents.txt"
fail=0
for want in '/usr/lib/.*libvoxkit\.so\.0\.1$' '/usr/include/voxkit/svo/svo\.h$' '/usr/include/voxkit/version\.h$' \
            '/usr/lib/.*cmake/voxkit/voxkitConfig\.cmake$' '/usr/lib/.*pkgconfig/voxkit\.pc$' '/usr/bin/svo_info$' \
            '/usr/bin/vox2svo$'; do
  grep -q "$want" "$WORK/contents.txt" || { echo "FAIL: nothing matches $want"; fail=1; }
done
if [ -n "$PY" ]; then
  grep -q '/usr/lib/python3/dist-packages/voxkit\..*\.so$' "$WORK/contents.txt" || {
    echo "FAIL: no Python module in /usr/lib/python3/dist-packages"; fail=1; }
  dpkg-deb -I "$DEB" | grep -q 'Depends:.*python3-numpy' || { echo "FAIL: no python3-numpy in Depends"; fail=1; }
fi
dpkg-deb -x "$DEB" "$WORK/root"
"$WORK/root/usr/bin/svo_info" --version
if [ -n "$PY" ]; then
  PYTHONPATH="$WORK/root/usr/lib/python3/dist-packages" "$PY" -c '
import sys, voxkit
lib = [l.split()[-1] for l in open("/proc/self/maps") if "libvoxkit.so" in l]
print("import voxkit", voxkit.__version__, "from", voxkit.__file__, "with", lib[0])
sys.exit(0 if lib and lib[0].startswith(sys.argv[1]) else 1)' "$WORK/root/usr/lib/" || {
    echo "FAIL: the unpacked module does not load the unpacked libvoxkit"; fail=1; }
fi
[ $fail = 0 ] && echo "package: ok"
exit $fail
