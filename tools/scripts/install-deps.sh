#!/usr/bin/env bash
# Installs the Debian packages Strata needs, only those that are missing. Idempotent.
#   install-deps.sh        what building `strata` and running the demo needs (README command 1)
#   install-deps.sh test   that, plus what the test suite needs (README command 2): GoogleTest, Google
#                          Benchmark, Bullet (the side-by-side peer), clang with libFuzzer, Slurm and MUNGE
#                          (the farm-bake test starts its own daemons), Chromium (the viewer's page test)
# Services the packages would start on installation are kept from starting: nothing installed is left running.
set -euo pipefail
mode="${1:-run}"
packages=(cmake g++ make pkg-config ccache libeigen3-dev libtbb-dev nlohmann-json3-dev libcli11-dev
          libassimp-dev librecast-dev libstb-dev libcpp-httplib-dev)
if [ "$mode" = test ]; then
  packages+=(libgtest-dev libbenchmark-dev libbullet-dev clang slurmctld slurmd slurm-client munge chromium)
elif [ "$mode" != run ]; then
  echo "usage: install-deps.sh [run|test]" >&2
  exit 2
fi
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
install() {
  echo "installing: $*"
  "${sudo_cmd[@]}" apt-get update -qq
  # Debian starts a daemon on installation unless policy-rc.d says no (exit 101): say no for this install
  # only, where no policy is in place already.
  local policy=/usr/sbin/policy-rc.d added_policy=0
  if [ ! -e "$policy" ]; then
    printf '#!/bin/sh\nexit 101\n' | "${sudo_cmd[@]}" tee "$policy" > /dev/null
    "${sudo_cmd[@]}" chmod 755 "$policy"
    added_policy=1
  fi
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "$@" || {
    local status=$?
    if [ $added_policy -eq 1 ]; then "${sudo_cmd[@]}" rm -f "$policy"; fi
    return $status
  }
  if [ $added_policy -eq 1 ]; then "${sudo_cmd[@]}" rm -f "$policy"; fi
}
# The browser viewer is bundled from npm packages at build time: any Node.js with npm will do (Debian's, or
# one installed from elsewhere that ships npm itself).
if ! command -v npm > /dev/null; then missing+=(nodejs npm); fi
if [ ${#missing[@]} -gt 0 ]; then install "${missing[@]}"; fi
# libFuzzer's runtime ships in a package named after clang's major version (tests/fuzz).
if [ "$mode" = test ] && [ ! -f "$(clang++ -print-runtime-dir)/libclang_rt.fuzzer-x86_64.a" ]; then
  install "libclang-rt-$(clang++ -dumpversion | cut -d. -f1)-dev"
fi
