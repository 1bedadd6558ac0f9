#!/usr/bin/env bash
# Installs the Debian packages Strata builds with, only those that are missing. Idempotent.
set -euo pipefail
packages=(cmake g++ make pkg-config ccache libeigen3-dev libtbb-dev nlohmann-json3-dev libcli11-dev
          libgtest-dev libbenchmark-dev libassimp-dev librecast-dev libstb-dev libbullet-dev)
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -eq 0 ]; then exit 0; fi
echo "installing: ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
