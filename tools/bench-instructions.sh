#!/bin/sh
# make bench-instructions: instructions per body-step inside nt_world_step, counted by
# callgrind (deterministic, unlike wall time on a shared host), for the scenes of the
# step's instruction targets. Each scene runs once (`ntile bench world SCENE --runs 1
# --min-ms 0`), which prints how many body-steps it took inside nt_world_step (every
# call adds the world's body count), so the division is exact.
NTILE=${1:-build/ntile}
if ! command -v valgrind >/dev/null 2>&1; then
    echo "bench-instructions: valgrind is not installed (Debian: apt-get install valgrind); nothing measured"
    exit 0
fi
printf '%-10s %16s %14s %18s %8s\n' scene instructions body-steps "instr/body-step" target
fail=0
for pair in particles:250 rain:1100 free:100 touching:120; do
    scene=${pair%%:*}
    target=${pair#*:}
    out=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null --toggle-collect=nt_world_step \
        "$NTILE" bench world "$scene" --runs 1 --min-ms 0 2>&1) || { echo "$out" | tail -5; exit 1; }
    ir=$(echo "$out" | sed -n 's/.*Collected : \([0-9]*\).*/\1/p' | tail -1)
    bs=$(echo "$out" | sed -n 's/.*body-steps inside nt_world_step: \([0-9]*\).*/\1/p' | tail -1)
    if [ -z "$ir" ] || [ -z "$bs" ] || [ "$bs" -eq 0 ]; then
        echo "bench-instructions: could not read the counts for $scene"
        exit 1
    fi
    per=$(awk -v a="$ir" -v b="$bs" 'BEGIN { printf "%.0f", a / b }')
    verdict=PASS
    [ "$per" -le "$target" ] || { verdict=FAIL; fail=1; }
    printf '%-10s %16s %14s %18s %8s %s\n' "$scene" "$ir" "$bs" "$per" "<= $target" "$verdict"
done
exit 0
