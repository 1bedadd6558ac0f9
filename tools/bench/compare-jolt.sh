#!/usr/bin/env bash
# compare-jolt.sh: Strata beside Jolt Physics on the same scenes, as one table anyone can rerun.
#
# Builds Jolt's PerformanceTest (Distribution) from a Jolt checkout you provide, in a folder outside this
# repository, then runs `strata bench` and Jolt's PerformanceTest alternately, scene by scene and thread
# count by thread count, and prints the median steps/s of each with the ratio and each build's instruction
# set. No Jolt code enters this repository.
#
#   tools/bench/compare-jolt.sh JOLT_SOURCE_DIR [options]
#     --runs N              alternated runs of every cell (default 5); the table shows medians
#     --threads "1 2"       thread counts (default "1 2")
#     --scenes "pyramid convex_vs_mesh"
#     --steps N             steps per run (default 500, as Jolt's PerformanceTest)
#     --jolt-isa avx2|sse4.2  Jolt's default build (AVX2, FMA where the CPU has them) or one without AVX
#     --strata PATH         the strata binary (default build/tools/strata); build it with
#                           -DSTRATA_ARCH=x86-64-v3 to compare against Jolt's AVX2 build
#     --solver strata|jolt   Strata's solver passes: its defaults, or Jolt's counts for the scene (default: jolt)
#     --work DIR            where Jolt is built (default ${TMPDIR:-/tmp}/strata-jolt-<isa>)
#     --jolt-binary PATH    a PerformanceTest already built (skips the build)
set -euo pipefail

usage() {
  sed -n '2,19p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
}

fail() {
  echo "compare-jolt: $*" >&2
  exit 2
}

[[ $# -ge 1 ]] || usage
[[ $1 == -h || $1 == --help ]] && usage
jolt_source=$1
shift
runs=5
threads="1 2"
scenes="pyramid convex_vs_mesh"
steps=500
jolt_isa=avx2
repo=$(cd "$(dirname "$0")/../.." && pwd)
strata=$repo/build/tools/strata
solver=jolt
work=""
jolt_binary=""
while [[ $# -gt 0 ]]; do
  [[ $# -ge 2 ]] || fail "$1 needs a value"
  case $1 in
    --runs) runs=$2 ;;
    --threads) threads=$2 ;;
    --scenes) scenes=$2 ;;
    --steps) steps=$2 ;;
    --jolt-isa) jolt_isa=$2 ;;
    --strata) strata=$2 ;;
    --solver) solver=$2 ;;
    --work) work=$2 ;;
    --jolt-binary) jolt_binary=$2 ;;
    *) fail "unknown option $1 (see --help)" ;;
  esac
  shift 2
done

is_count() { [[ $1 =~ ^[1-9][0-9]{0,5}$ ]]; }
is_count "$runs" || fail "--runs must be a whole number from 1 (got '$runs')"
is_count "$steps" || fail "--steps must be a whole number from 1 (got '$steps')"
for t in $threads; do { is_count "$t" && [[ $t -le 256 ]]; } || fail "--threads takes counts from 1 to 256 (got '$t')"; done
[[ -n ${threads// /} ]] || fail "--threads is empty"
case $jolt_isa in avx2 | sse4.2) ;; *) fail "--jolt-isa is avx2 or sse4.2 (got '$jolt_isa')" ;; esac
case $solver in strata | jolt) ;; *) fail "--solver is strata or jolt (got '$solver')" ;; esac
declare -A jolt_scene=([pyramid]=Pyramid [convex_vs_mesh]=ConvexVsMesh)
for s in $scenes; do [[ -n ${jolt_scene[$s]:-} ]] || fail "no Jolt scene matches '$s' (pyramid, convex_vs_mesh)"; done
[[ -x $strata ]] || fail "no strata binary at $strata (build it first, or pass --strata)"

# --- Jolt's PerformanceTest, built outside this repository --------------------------------------------
if [[ -z $jolt_binary ]]; then
  [[ -f $jolt_source/Build/CMakeLists.txt && -d $jolt_source/PerformanceTest ]] ||
    fail "$jolt_source is not a Jolt Physics checkout (no Build/CMakeLists.txt and PerformanceTest/)"
  work=${work:-${TMPDIR:-/tmp}/strata-jolt-$jolt_isa}
  case $(cd "$(dirname "$work")" 2>/dev/null && pwd)/ in "$repo"/*) fail "--work must lie outside this repository" ;; esac
  isa_flags=()
  if [[ $jolt_isa == sse4.2 ]]; then
    isa_flags=(-DUSE_AVX=OFF -DUSE_AVX2=OFF -DUSE_AVX512=OFF -DUSE_LZCNT=OFF -DUSE_TZCNT=OFF -DUSE_F16C=OFF
      -DUSE_FMADD=OFF)
  fi
  echo "compare-jolt: building Jolt's PerformanceTest ($jolt_isa, Distribution) in $work" >&2
  cmake -S "$jolt_source/Build" -B "$work" -DCMAKE_BUILD_TYPE=Distribution -DTARGET_UNIT_TESTS=OFF \
    -DTARGET_HELLO_WORLD=OFF -DTARGET_SAMPLES=OFF -DTARGET_VIEWER=OFF -DTARGET_PERFORMANCE_TEST=ON \
    -DENABLE_ALL_WARNINGS=OFF "${isa_flags[@]}" >"$work.configure.log" 2>&1 ||
    fail "configuring Jolt failed (see $work.configure.log)"
  cmake --build "$work" --target PerformanceTest -j "$(nproc)" >"$work.build.log" 2>&1 ||
    fail "building Jolt's PerformanceTest failed (see $work.build.log)"
  jolt_binary=$(find "$work" -name PerformanceTest -type f -perm -u+x | head -n 1)
  [[ -n $jolt_binary ]] || fail "the build left no PerformanceTest in $work"
fi
[[ -x $jolt_binary ]] || fail "no Jolt PerformanceTest at $jolt_binary"

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

# One run of each engine; each prints steps/s (and the instruction set it was built for, once).
run_strata() { # scene threads
  "$strata" bench --scene "$1" --threads "$2" --steps "$steps" --solver "$solver" --no-bullet \
    >"$scratch/strata.out" 2>&1 || { cat "$scratch/strata.out" >&2; fail "strata bench failed"; }
  local rate isa used
  rate=$(awk '$1 == "strata" && $2 ~ /^[0-9]+$/ && $3 ~ /^[0-9.]+$/ { print $3 }' "$scratch/strata.out" | tail -n 1)
  isa=$(sed -n 's/^strata bench: built for //p' "$scratch/strata.out" | tr ' ' '_')
  used=$(sed -n 's/.*, solver \(.*\), sleeping .*/\1/p' "$scratch/strata.out" | head -n 1 | tr ' ' '_')
  [[ -n $rate && -n $isa && -n $used ]] || { cat "$scratch/strata.out" >&2; fail "strata bench printed no figure"; }
  echo "$rate $isa $used"
}

run_jolt() { # scene threads
  (cd "$(dirname "$jolt_binary")" && "$jolt_binary" "-s=${jolt_scene[$1]}" -q=Discrete "-t=$2" "-i=$steps") \
    >"$scratch/jolt.out" 2>&1 || { cat "$scratch/jolt.out" >&2; fail "Jolt's PerformanceTest failed"; }
  local rate config
  rate=$(awk -F', *' '$1 == "Discrete" && NF >= 3 { print $3 }' "$scratch/jolt.out" | tail -n 1)
  [[ -n $rate ]] || { cat "$scratch/jolt.out" >&2; fail "no 'Discrete, threads, steps/s' line from Jolt"; }
  config=$(grep -m1 -i "instructions:" "$scratch/jolt.out" | sed 's/.*[Ii]nstructions: *//; s/ *(.*//' | tr ' ' '_')
  echo "$rate ${config:-unknown}"
}

median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

declare -A strata_rates jolt_rates solver_text
strata_isa="" jolt_config=""
for ((run = 1; run <= runs; ++run)); do
  for scene in $scenes; do
    for t in $threads; do
      # Alternate which engine goes first, so neither always runs on a machine the other just warmed.
      if ((run % 2 == 1)); then order="strata jolt"; else order="jolt strata"; fi
      for engine in $order; do
        rate=""
        if [[ $engine == strata ]]; then
          read -r rate strata_isa solver_used < <(run_strata "$scene" "$t") || true
          [[ -n ${rate:-} ]] || fail "no figure from strata for $scene at $t thread(s)"
          solver_text[$scene]=${solver_used//_/ }
          strata_rates[$scene,$t]+="$rate "
        else
          read -r rate jolt_config < <(run_jolt "$scene" "$t") || true
          [[ -n ${rate:-} ]] || fail "no figure from Jolt for $scene at $t thread(s)"
          jolt_rates[$scene,$t]+="$rate "
        fi
      done
      echo "compare-jolt: run $run of $runs, $scene, $t thread(s)" >&2
    done
  done
done

echo "Strata: $strata, instruction set ${strata_isa//_/ }"
for scene in $scenes; do echo "  $scene: solver ${solver_text[$scene]}"; done
echo "Jolt: $jolt_binary, instructions ${jolt_config//_/ }, -q=Discrete, its own passes for each scene"
echo "median steps/s of $runs alternated runs of $steps steps"
printf '%-16s %8s %14s %14s %12s\n' scene threads "Strata steps/s" "Jolt steps/s" Strata/Jolt
for scene in $scenes; do
  for t in $threads; do
    s=$(echo "${strata_rates[$scene,$t]}" | median)
    j=$(echo "${jolt_rates[$scene,$t]}" | median)
    printf '%-16s %8s %14.1f %14.1f %11.2fx\n' "$scene" "$t" "$s" "$j" "$(awk -v a="$s" -v b="$j" 'BEGIN { print a / b }')"
  done
done
