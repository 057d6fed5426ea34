#!/bin/sh
# ctest test_vdb_export: svo_info --to-vdb read back through OpenVDB (the
# shim's reader, vdb_check): the active voxels and their colours must be the
# cells `svo_info --dump` prints, flattened (default) and per instance
# (--vdb-models); the flattened file converts back (vox2svo --color color) to
# the same cells; vdb_print (openvdb-tools) where installed counts the same
# voxels. Scenes: the generated demo island, and from the corpus (skipped
# with a message when absent) a 41-model .vox, the Duck and the OpenVDB sphere.
# Usage: test_vdb_export.sh BIN_DIR VDB_CHECK CORPUS_DIR WORK_DIR
set -eu
BIN=$1 CHECK=$2 CORPUS=${VX_CORPUS_DIR:-$3} WORK=$4
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"
fail=0

run() { # NAME SVO
  name=$1 svo=$2
  "$BIN/svo_info" "$svo" --dump | cut -d' ' -f1-6 | sort >"$name.dump"
  # flattened: a cell that several instances set takes the last one's colour
  "$BIN/svo_info" "$svo" --dump | awk '{ c[$1 " " $2 " " $3] = $4 " " $5 " " $6 } END { for (k in c) print k, c[k] }' |
    sort >"$name.cells"
  colors=$("$BIN/svo_info" "$svo" --to-vdb "$name.vdb" | grep -c colours || true)
  "$CHECK" "$name.vdb" "$svo" 2>"$name.check.log" | sort -u >"$name.vdb.cells" || { cat "$name.check.log"; fail=1; }
  if cmp -s "$name.cells" "$name.vdb.cells"; then
    echo "ok    $name: --to-vdb has the $(wc -l <"$name.cells") cells of --dump with their colours"
  else
    echo "FAIL  $name: --to-vdb differs from --dump"; diff "$name.cells" "$name.vdb.cells" | head -5; fail=1
  fi
  "$BIN/svo_info" "$svo" --to-vdb "$name-models.vdb" --vdb-models -q
  "$CHECK" "$name-models.vdb" "$svo" 2>"$name.check-models.log" | sort >"$name.models.cells" || {
    cat "$name.check-models.log"; fail=1; }
  if cmp -s "$name.dump" "$name.models.cells"; then
    echo "ok    $name: --vdb-models placed by the grids' transforms gives every --dump line ($(tail -n 1 "$name.check-models.log"))"
  else
    echo "FAIL  $name: --vdb-models differs from --dump"; diff "$name.dump" "$name.models.cells" | head -5; fail=1
  fi
  if [ "$colors" = 1 ]; then set -- --color color; else set --; fi
  "$BIN/vox2svo" "$name.vdb" "$name-back.svo" "$@" >/dev/null
  "$BIN/svo_info" "$name-back.svo" --dump | cut -d' ' -f1-6 | sort -u >"$name.back.cells"
  if cmp -s "$name.cells" "$name.back.cells"; then
    echo "ok    $name: the .vdb converts back to the same cells and colours"
  else
    echo "FAIL  $name: the .vdb converts back to other cells"; diff "$name.cells" "$name.back.cells" | head -5; fail=1
  fi
  if command -v vdb_print >/dev/null 2>&1; then
    n=$(vdb_print -l "$name.vdb" | sed -n 's/.*Number of active voxels: *\([0-9,]*\).*/\1/p' | head -n 1 | tr -d ,)
    if [ "$n" = "$(wc -l <"$name.cells" | tr -d ' ')" ]; then
      echo "ok    $name: vdb_print reads $n active voxels in 'density'"
    else
      echo "FAIL  $name: vdb_print reads '$n' active voxels"; fail=1
    fi
  fi
}

"$BIN/vox2svo" --write-demo demo.vox >/dev/null
"$BIN/vox2svo" demo.vox demo.svo --keep-hidden >/dev/null
run demo demo.svo
command -v vdb_print >/dev/null 2>&1 || echo "skip: vdb_print not installed (openvdb-tools)"

# a write that cannot happen leaves nothing and names the file
if "$BIN/svo_info" demo.svo --to-vdb no/such/dir/out.vdb -q 2>err.txt; then
  echo "FAIL  --to-vdb into a missing folder succeeded"; fail=1
elif grep -q "no/such/dir/out.vdb" err.txt && [ -z "$(ls no 2>/dev/null)" ]; then
  echo "ok    a failed write names the file: $(cat err.txt)"
else
  echo "FAIL  a failed write: $(cat err.txt)"; fail=1
fi

for spec in vox/ogt_test_multiple_model_scene.vox: gltf/julian_Duck.glb:--res=64 vdb/mjurczyk_sphere.vdb:; do
  rel=${spec%%:*} opt=$(echo "${spec#*:}" | tr = ' ')
  src=$CORPUS/$rel
  if [ ! -f "$src" ]; then echo "skip: $src not found"; continue; fi
  name=$(basename "$rel" | tr . _)
  # shellcheck disable=SC2086
  "$BIN/vox2svo" "$src" "$name.svo" $opt >/dev/null
  run "$name" "$name.svo"
done
exit $fail
