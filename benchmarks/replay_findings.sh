#!/usr/bin/env bash
# After benchmarks/fuzz_campaign.sh: every exported finding, run as an ordinary vector over
# exec: at 20 ms timers, must fail the variant it was found on and pass the unbroken reference.
#   benchmarks/replay_findings.sh [DIR]      (default /tmp/ptpcert-fuzz)
set -u
cd "$(dirname "$0")/.."
DIR=${1:-/tmp/ptpcert-fuzz}
bad=0
for d in "$DIR"/*/; do
    m=$(basename "$d")
    ls "$d"/*.toml >/dev/null 2>&1 || continue
    if [ "$m" = unbroken ]; then echo "unbroken: has findings (!)"; bad=1; continue; fi
    prio=$(python3 -c "from ptpcert.procedures.p3964.mutants import MUTANTS; print(MUTANTS['$m'].profile.get('priority', 'low'))")
    prof="$DIR/profile-$prio.toml"
    n=$(ls "$d"/*.toml | wc -l)
    ptpcert run --iut "exec:ptpcert iut --cdt-ms 20 --adt-ms 20 --parmrk --priority $prio --mutant $m" \
        --profile "$prof" --vectors "$d" --vectors-only > "$DIR/$m.replay-mutant.log" 2>&1
    rm_=$?
    ptpcert run --iut "exec:ptpcert iut --cdt-ms 20 --adt-ms 20 --parmrk --priority $prio" \
        --profile "$prof" --vectors "$d" --vectors-only > "$DIR/$m.replay-unbroken.log" 2>&1
    ru=$?
    failed=$(grep -c -E "^\s*(FAIL|fail)" "$DIR/$m.replay-mutant.log")
    verdict=ok; { [ $rm_ -eq 1 ] && [ $ru -eq 0 ]; } || { verdict=WRONG; bad=1; }
    echo "$m: $n vector(s); variant exit $rm_ ($failed failing line(s)), unbroken exit $ru: $verdict"
done
exit $bad
