#!/usr/bin/env bash
# Installs the Debian packages Strata builds with, only those that are missing. Idempotent.
set -euo pipefail
packages=(cmake g++ make pkg-config ccache libeigen3-dev libtbb-dev nlohmann-json3-dev libcli11-dev
          libgtest-dev libbenchmark-dev libassimp-dev librecast-dev libstb-dev libbullet-dev clang
          slurmctld slurmd slurm-client munge chromium)
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
install() {
  echo "installing: $*"
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "$@"
}
# The browser viewer is bundled from npm packages at build time: any Node.js with npm will do (Debian's, or
# one installed from elsewhere that ships npm itself).
if ! command -v npm > /dev/null; then missing+=(nodejs npm); fi
if [ ${#missing[@]} -gt 0 ]; then install "${missing[@]}"; fi
# libFuzzer's runtime ships in a package named after clang's major version (tests/fuzz).
if [ ! -f "$(clang++ -print-runtime-dir)/libclang_rt.fuzzer-x86_64.a" ]; then
  install "libclang-rt-$(clang++ -dumpversion | cut -d. -f1)-dev"
fi
