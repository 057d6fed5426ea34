# ray8 (issue 21, twenty-third sitting): the lines both H200 payloads (ray8_b1_gpu.sh, ray8_b2_gpu.sh) share, sourced
# by them here (the payloads carried them inline): the time left of a limit, the clock, a time stamp per line, the
# rows' filter. BINS: the binaries to unpack (A B or A B C).
s0=$(date +%s); left() { echo $(( $1 * ${TS:-1} - ($(date +%s) - s0) )); }
T=/tmp/ray8; rm -rf $T; mkdir -p $T; for x in $BINS; do gunzip -c ${x}_render_bench.gz > $T/$x; chmod +x $T/$x; done
tar xzf k.tgz -C $T
smi() { nvidia-smi --query-gpu=clocks.sm,clocks.max.sm,clocks.mem,power.draw,temperature.gpu,pstate,clocks_throttle_reasons.active --format=csv,noheader 2>/dev/null | head -1; }
stamp() { while IFS= read -r l; do printf '%s %s\n' "$(date -u +%T.%2N)" "$l"; done; }
flt() { sed -u -E "s|$T/||g; s/  *\[warps[^]]*\]//; s/^(.{330}).*/\1/"; }
F='^scene|^eph|^ogt|^terrain|^  \(|px differ|^device|^render_bench'
