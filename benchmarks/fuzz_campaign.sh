#!/usr/bin/env bash
# Level-2 fuzzing campaign: the unbroken reference implementation and every broken variant,
# each as a real process over exec: at 20 ms timers, BUDGET seconds each (default 120).
#   benchmarks/fuzz_campaign.sh [BUDGET [DIR [NAME ...]]]
# NAMEs choose IUTs ("unbroken" and/or mutant names); default: unbroken and every mutant.
# Prints one line per IUT: examples, findings. Findings go to DIR/<name>/ (default /tmp/ptpcert-fuzz).
set -u
cd "$(dirname "$0")/.."
BUDGET=${1:-120}
DIR=${2:-/tmp/ptpcert-fuzz}
shift 2 2>/dev/null || shift $#
SEED=${SEED:-20261122}
command -v ptpcert >/dev/null || { echo "ptpcert is not installed: python3 -m pip install -e ." >&2; exit 2; }
run() {  # name, url, priority
    prof="$DIR/profile-$3.toml"
    sed "s/priority = \"low\"/priority = \"$3\"/" conformance/profiles/reference-20ms.toml > "$prof"
    rm -rf "${DIR:?}/$1"
    log="$DIR/$1.log"
    ptpcert fuzz --iut "$2" --profile "$prof" --budget "$BUDGET" --seed "$SEED" --export "$DIR/$1" > "$log" 2>&1
    rc=$?
    out=$(grep -E "examples in" "$log")
    if [ -z "$out" ]; then out="no summary (exit $rc): $(tail -n 3 "$log" | tr '\n' ' ')"; fi
    echo "$1: $out"
}
mkdir -p "$DIR"
names=("$@")
if [ ${#names[@]} -eq 0 ]; then
    names=(unbroken $(python3 -c "from ptpcert.procedures.p3964.mutants import MUTANTS; print(' '.join(MUTANTS))"))
fi
for m in "${names[@]}"; do
    if [ "$m" = unbroken ]; then
        run unbroken "exec:ptpcert iut --cdt-ms 20 --adt-ms 20 --parmrk" low
        continue
    fi
    prio=$(python3 -c "from ptpcert.procedures.p3964.mutants import MUTANTS; print(MUTANTS['$m'].profile.get('priority', 'low'))") || exit 2
    run "$m" "exec:ptpcert iut --cdt-ms 20 --adt-ms 20 --parmrk --priority $prio --mutant $m" "$prio"
done
