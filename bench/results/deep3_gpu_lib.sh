# deep3 (issue 21, twenty-fourth sitting): the lines both H200 payloads (deep3_b1_gpu.sh, deep3_b2_gpu.sh) share,
# sourced by them here (the payloads carried them inline): unpack A, B, C and k.tgz, then gpu_payload_lib.sh's
# helpers, a --kernels list (kl) and the end (finish). BATCH: the batch's number; LIM: the whole run's seconds.
T=/tmp/deep3; rm -rf $T; mkdir -p $T; for x in A B C; do gunzip -c ${x}_render_bench.gz > $T/$x; chmod +x $T/$x; done
tar xzf k.tgz -C $T
. "$(dirname "${BASH_SOURCE[0]}")/gpu_payload_lib.sh"
F='^scene|^terrain|^  \(|px differ|^device|^render_bench|^stats: trace \[' # (deep3's: the trace kernels' stats only)
echo "== deep3 batch $BATCH on $(gpu_name) $(nproc) CPUs $(date -u +%T); A = main $(cat A_COMMIT), B = $(cat B_COMMIT), C = $(cat C_COMMIT)"
clock_start
kl() { local r=; for k in ${1//,/ }; do r="$r${r:+,}$T/$k.spv@c1"; done; echo $r; }
finish() { payload_end deep3; }
