#!/bin/sh
# Runs every libFuzzer target for SECONDS seconds each (default 60), seeded
# with the corpus. Builds them with clang in build-fuzz. Any crash fails.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]    # CI: scripts/fuzz.sh 10
#
# Targets: vox_fuzz (.vox), svo_fuzz (.svo), svo_reader_fuzz (.svo through the model
# reader, against the whole read), gltf_fuzz (glTF with PNG/JPEG
# base colour textures), probes_fuzz (.probes), vdb_fuzz (OpenVDB through the
# shim). Each starts from its seeds (tests/fuzz/*_seeds, tests/probes/
# fuzz_seeds, the shared corpus) plus its regression inputs (tests/fuzz/
# regress/NAME/, which ctest replays as NAME_fuzz_regress), with a dictionary
# (tests/fuzz/NAME.dict). Findings stay in build-fuzz/work-TARGET (the growing
# corpus, kept between runs) and build-fuzz/TARGET.log; a crash is written to
# build-fuzz/crash-* and fails the script. VX_FUZZ_JOBS=N runs N processes per
# target (libFuzzer -fork) for long campaigns.
#
# Campaign settings (environment):
#   VX_FUZZ_MAX_LEN=BYTES  no input longer than BYTES (-max_len), and seed files
#                          longer than that are left out (default 1 MiB; vdb_fuzz
#                          64 KiB: its seeds are 10-20 KB, and OpenVDB's reader is
#                          most of the time an input takes). The shared corpus's
#                          models of hundreds of KB make vox_fuzz and gltf_fuzz
#                          run 20-40 times slower: 100000 leaves them out.
#   VX_FUZZ_RUNS=N         stop each target after N executions (-runs), or at
#                          SECONDS, whichever comes first
#   VX_FUZZ_TIMEOUT=S      an input running longer is a failure (default 10)
set -eu
cd "$(dirname "$0")/.."
SECONDS_EACH=${1:-60}
[ $# -gt 0 ] && shift
CORPUS=${VX_CORPUS_DIR:-../shared/corpus}
JOBS=${VX_FUZZ_JOBS:-1}
TIMEOUT=${VX_FUZZ_TIMEOUT:-10}
# Libraries get coverage instrumentation (fuzzer-no-link) so libFuzzer sees
# inside them; only the fuzz targets link the libFuzzer main. Third-party
# shared libraries (libopenvdb, libtinygltf with its stb_image, zlib, blosc)
# are Debian's and not instrumented: vdb_fuzz and gltf_fuzz are guided by our
# shims' coverage and find memory errors in our code, ASan's interceptors
# still check what those libraries pass through malloc/memcpy.
F="-fsanitize=fuzzer-no-link,address,undefined"
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVX_FUZZ=ON \
    -DCMAKE_C_FLAGS="$F" -DCMAKE_CXX_FLAGS="$F" \
    -DVX_WITH_VULKAN=OFF -DVX_WITH_OPENVDB=ON -DVX_WITH_OIIO=OFF >/dev/null
want=${*:-vox_fuzz svo_fuzz svo_reader_fuzz gltf_fuzz probes_fuzz vdb_fuzz pnm_fuzz}
targets=""
for t in $want; do
    if cmake --build build-fuzz --target "$t" -j"$(nproc)" >"build-fuzz/build-$t.log" 2>&1; then
        targets="$targets $t"
    else
        echo "fuzz: $t not built (see build-fuzz/build-$t.log)"
    fi
done
status=0
for t in $targets; do
    n=${t%_fuzz}
    work="build-fuzz/work-$t"
    mkdir -p "$work"
    seeds=""
    case $t in
        vox_fuzz) seeds="$CORPUS/vox" ;;
        svo_fuzz) seeds="tests/fuzz/svo_seeds" ;;
        svo_reader_fuzz) seeds="tests/fuzz/svo_seeds tests/fuzz/svo_reader_seeds" ;;
        gltf_fuzz) seeds="tests/fuzz/gltf_seeds $CORPUS/gltf" ;;
        probes_fuzz) seeds="tests/probes/fuzz_seeds" ;;
        vdb_fuzz) seeds="tests/fuzz/vdb_seeds $CORPUS/vdb" ;;
    esac
    maxlen=1048576
    [ "$t" = vdb_fuzz ] && maxlen=65536
    maxlen=${VX_FUZZ_MAX_LEN:-$maxlen}
    # the seeds no longer than maxlen, linked into one folder (libFuzzer would
    # cut longer ones to maxlen bytes: broken files that only cost time)
    sd="build-fuzz/seeds-$t"
    rm -rf "$sd"
    mkdir -p "$sd"
    left=0
    for d in $seeds "tests/fuzz/regress/$n"; do
        [ -d "$d" ] || continue
        find "$d" -type f -size -"$((maxlen + 1))"c | while IFS= read -r f; do
            case $f in /*) src=$f ;; *) src=$PWD/$f ;; esac
            ln -sf "$src" "$sd/$(printf %s "$f" | tr '/ .' '___' | sed 's/^_*//')"
        done
        left=$((left + $(find "$d" -type f -size +"$maxlen"c | wc -l)))
    done
    [ "$left" -gt 0 ] && echo "fuzz: $t: $left seed files over $maxlen bytes left out"
    opts="-max_total_time=$SECONDS_EACH -rss_limit_mb=4096 -max_len=$maxlen -timeout=$TIMEOUT -print_final_stats=1"
    [ -n "${VX_FUZZ_RUNS:-}" ] && opts="$opts -runs=$VX_FUZZ_RUNS"
    opts="$opts -artifact_prefix=build-fuzz/"
    dict=$n
    [ "$n" = svo_reader ] && dict=svo # the same format
    [ -f "tests/fuzz/$dict.dict" ] && opts="$opts -dict=tests/fuzz/$dict.dict"
    [ "$JOBS" -gt 1 ] && opts="$opts -fork=$JOBS -ignore_crashes=0"
    env=""
    if [ "$t" = vdb_fuzz ]; then
        # OpenVDB sizes buffers from file fields (metadata values, compressed
        # chunks) and uses operator new: allocations over 256 MiB fail as
        # std::bad_alloc (-> VX_ERR_NOMEM) instead of stalling ASan for
        # seconds per input. OpenVDB's known leak on error paths is
        # suppressed, and the target reclaims those blocks after each input
        # (tests/fuzz/vdb_fuzz.c) so memory stays flat.
        env="ASAN_OPTIONS=allocator_may_return_null=1:max_allocation_size_mb=256"
        env="$env LSAN_OPTIONS=suppressions=tests/convert/vdb_lsan.supp:print_suppressions=0"
        opts="$opts -malloc_limit_mb=8200"
    fi
    echo "fuzz: $t for ${SECONDS_EACH}s"
    # shellcheck disable=SC2086
    if ! env $env "build-fuzz/bin/$t" $opts "$work" "$sd" >"build-fuzz/$t.log" 2>&1; then
        tail -n 40 "build-fuzz/$t.log"
        echo "fuzz: $t found a failure (input saved as build-fuzz/crash-*, leak-*, timeout-* or oom-*)"
        status=1
        continue
    fi
    # executions, coverage, corpus: the last status line and the final stats
    # (with VX_FUZZ_JOBS > 1 the parent's last "#N: cov: ..." line, which
    # counts the timeouts and out-of-memory inputs the jobs skipped)
    grep -E '^#[0-9]+[[:space:]]+DONE|^#[0-9]+: cov:' "build-fuzz/$t.log" | tail -n 1 || true
    grep -E '^stat::(number_of_executed_units|slowest_unit_time_sec|peak_rss_mb)' "build-fuzz/$t.log" || true
done
exit $status
