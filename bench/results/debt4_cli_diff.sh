#!/bin/bash
# usage: debt4_cli_diff.sh BIN_DIR OUT_FILE: svo_bake's help and its errors for each option (missing or bad argument)
B=$1; O=$2; : > $O
W=$(mktemp -d); cd $W
t=svo_bake
run() { echo "=== $t $*" >> $O; timeout 10 $B/$t "$@" >> $O 2>&1 < /dev/null; echo "rc=$?" >> $O; }
run --help; run -h; run; run -x; run --bogus; run -version
for opt in $($B/$t --help 2>&1 | grep -o -- '--[a-z0-9][a-z0-9-]*' | sort -u); do
  run $opt; run $opt zz; run $opt -1; run $opt 99999999999; run a.svo $opt zz; run a.svo b $opt 0; run a.svo b $opt
done
rm -rf $W
