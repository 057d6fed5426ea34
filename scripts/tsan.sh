#!/bin/sh
# ThreadSanitizer over the suite's tests of our threaded code: a build with
# -fsanitize=thread in build-tsan, then ctest on the tests named (default: the
# library's multi-threaded parts that run without a GPU, below). A race report
# fails its test (TSan's exit code); reports in the uninstrumented libraries
# (lavapipe, TBB under OpenVDB) are suppressed by tests/tsan.supp. Not in CI:
# the instrumented build and runs take about 15 minutes on two cores
# (docs/RELIABILITY.md, "Data races").
#
#   scripts/tsan.sh [CTEST_REGEX]
set -eu
cd "$(dirname "$0")/.."
REGEX=${1:-'^(svo_build|core_jobs|core_crc|svo_io|svo_fuzz_replay|svo_reader_fuzz_replay|svo_pack|svo_edit|svo_reader_model|svo_reader_rewind|mesh_test|mesh_scene_test|vdb_convert|test_vox_svo|test_vox|test_render_cpu|test_pathtrace|test_probes|test_alloc_fail|test_compact|test_compact_load|test_compact_page|test_up_axis|test_vdb_export|test_material_key|test_view_editor)$'}
F="-fsanitize=thread -O1 -g"
cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVX_BENCH=OFF -DCMAKE_C_FLAGS="$F" -DCMAKE_CXX_FLAGS="$F" \
    -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=thread -DCMAKE_SHARED_LINKER_FLAGS=-fsanitize=thread >/dev/null
cmake --build build-tsan -j"$(nproc)"
# detect_deadlocks=0: lavapipe's LLVM JIT holds more than the 64 locks a thread the lock-order detector can
# track (a CHECK failure inside ThreadSanitizer, not a finding)
export TSAN_OPTIONS="suppressions=$PWD/tests/tsan.supp halt_on_error=0 history_size=4 detect_deadlocks=0"
ctest --test-dir build-tsan --output-on-failure -j"$(nproc)" --timeout 1800 -R "$REGEX"
