#!/usr/bin/env bash
# tools/bench/compare-jolt.sh against a stand-in for Jolt's PerformanceTest (a script printing what Jolt
# prints), with the real strata binary: the table holds the medians and ratios of what each side printed, the
# stand-in gets Jolt's arguments, and bad arguments or output are refused with a message and exit 2.
#   CompareJoltScript.sh STRATA_BINARY
set -euo pipefail
strata=$1
here=$(cd "$(dirname "$0")" && pwd)
script=$here/../../tools/bench/compare-jolt.sh
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

failures=0
check() { # description, command...
  local what=$1
  shift
  if "$@"; then echo "ok: $what"; else echo "FAILED: $what"; failures=$((failures + 1)); fi
}

# The stand-in answers 100, 300 and 200 steps/s in turn (median 200) and records its arguments.
cat >"$scratch/PerformanceTest" <<STUB
#!/usr/bin/env bash
echo "\$*" >>"$scratch/arguments"
count=\$(wc -l <"$scratch/arguments")
rates=(100 300 200)
echo "Single precision x86 64-bit with instructions: SSE2 SSE4.1 SSE4.2 (Multi Threaded) (32-bit ObjectLayer)"
echo "Running scene: Pyramid"
echo "Motion Quality, Thread Count, Steps / Second, Hash"
echo "Discrete, 1, \${rates[\$(( (count - 1) % 3 ))]}.000000, 0x1234"
STUB
chmod +x "$scratch/PerformanceTest"

output=$("$script" /nonexistent --jolt-binary "$scratch/PerformanceTest" --strata "$strata" --runs 3 --steps 5 \
  --threads 1 --scenes pyramid 2>"$scratch/errors")
echo "$output"
check "three runs of the stand-in, each with Jolt's arguments" \
  test "$(grep -c -- '-s=Pyramid -q=Discrete -t=1 -i=5' "$scratch/arguments")" -eq 3
check "the Jolt column is the median of what it printed" grep -Eq '^pyramid +1 +[0-9.]+ +200\.0 ' <<<"$output"
row=$(grep -E '^pyramid +1 ' <<<"$output")
read -r _ _ strata_rate jolt_rate ratio <<<"$row"
check "the ratio is Strata's median over Jolt's" \
  awk -v s="$strata_rate" -v j="$jolt_rate" -v r="${ratio%x}" 'BEGIN { exit !(s > 0 && (s / j - r) ^ 2 < 1e-4) }'
check "both instruction sets are named" grep -q 'instruction set x86-64' <<<"$output"
check "Jolt's instructions are named" grep -q 'instructions SSE2 SSE4.1 SSE4.2' <<<"$output"
check "Strata's solver for the scene is named" grep -q 'pyramid: solver jolt: 1 substep x (10 velocity + 2 relax' <<<"$output"

# shellcheck disable=SC2317  # called through check
refused() { # expected message, arguments...
  local message=$1
  shift
  local status=0
  "$script" "$@" >/dev/null 2>"$scratch/refusal" || status=$?
  [[ $status -eq 2 ]] && grep -q -- "$message" "$scratch/refusal"
}
stub=(--jolt-binary "$scratch/PerformanceTest" --strata "$strata")
check "--runs 0 is refused" refused "--runs must be" /nonexistent "${stub[@]}" --runs 0
check "a word for a thread count is refused" refused "--threads takes" /nonexistent "${stub[@]}" --threads "1 two"
check "an unknown scene is refused" refused "no Jolt scene matches 'ragdolls'" /nonexistent "${stub[@]}" --scenes ragdolls
check "an unknown instruction set is refused" refused "--jolt-isa is" /nonexistent "${stub[@]}" --jolt-isa avx512
check "an unknown option is refused" refused "unknown option --fast" /nonexistent "${stub[@]}" --fast 1
check "a folder that is not a Jolt checkout is refused" refused "is not a Jolt Physics checkout" "$scratch" \
  --strata "$strata"
check "a missing strata binary is refused" refused "no strata binary" /nonexistent --jolt-binary \
  "$scratch/PerformanceTest" --strata "$scratch/none"
printf '#!/usr/bin/env bash\necho "Invalid scene"\n' >"$scratch/Broken"
chmod +x "$scratch/Broken"
check "a Jolt that prints no figure is refused" refused "no 'Discrete, threads, steps/s' line" /nonexistent \
  --jolt-binary "$scratch/Broken" --strata "$strata" --runs 1 --steps 5 --threads 1 --scenes pyramid
exit $((failures > 0))
