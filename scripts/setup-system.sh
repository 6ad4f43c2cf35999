#!/usr/bin/env bash
# Install the Debian packages satgnc builds against, only those missing; sudo when not root.
set -euo pipefail
pkgs=(g++ make libeigen3-dev libsundials-dev libgtest-dev libbenchmark-dev liberfa-dev libpugixml-dev libtomlplusplus-dev ninja-build python3-dev python3-venv)
missing=()
for p in "${pkgs[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
# A non-Debian python3 (pyenv, conda) brings its own venv and headers.
if python3 -c 'import venv, sysconfig, os; assert os.path.exists(sysconfig.get_paths()["include"] + "/Python.h")' 2>/dev/null; then
  missing=("${missing[@]/python3-dev}"); missing=("${missing[@]/python3-venv}")
fi
missing=($(printf '%s\n' "${missing[@]}" | sed '/^$/d'))
[ ${#missing[@]} -eq 0 ] && exit 0
echo "satgnc: installing system packages: ${missing[*]}"
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
