#!/usr/bin/env bash
# Level-2 fuzzing campaign: the unbroken reference implementation and every broken variant,
# each as a real process over exec: at 20 ms timers, BUDGET seconds each (default 120).
# Prints one line per IUT: examples, findings. Findings go to DIR/<variant>/ (default /tmp/ptpcert-fuzz).
set -u
cd "$(dirname "$0")/.."
BUDGET=${1:-120}
DIR=${2:-/tmp/ptpcert-fuzz}
SEED=${SEED:-20261122}
run() {  # name, url, priority
    prof="$DIR/profile-$3.toml"
    sed "s/priority = \"low\"/priority = \"$3\"/" conformance/profiles/reference-20ms.toml > "$prof"
    out=$(ptpcert fuzz --iut "$2" --profile "$prof" --budget "$BUDGET" --seed "$SEED" --export "$DIR/$1" 2>&1 | grep -E "examples in")
    echo "$1: $out"
}
mkdir -p "$DIR"
run unbroken "exec:ptpcert iut --cdt-ms 20 --adt-ms 20 --parmrk" low
for m in $(python3 -c "from harness.mutants import MUTANTS; print(' '.join(MUTANTS))"); do
    prio=$(python3 -c "from harness.mutants import MUTANTS; print(MUTANTS['$m'].profile.get('priority', 'low'))")
    run "$m" "exec:ptpcert iut --cdt-ms 20 --adt-ms 20 --parmrk --priority $prio --mutant $m" "$prio"
done
