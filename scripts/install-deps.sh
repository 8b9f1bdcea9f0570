#!/usr/bin/env bash
# Installs the Debian 12 packages PowderDPM needs, if any is missing.
# As root: apt-get installs what is missing. Otherwise: prints what to install and exits 1.
# Quick no-op when everything is present.
set -euo pipefail

# python3 (standard library only) runs the validation and analysis scripts and one self-test; libvtk9-dev
# pulls it in anyway, it is named so that nothing depends on that; lld links the benchmark drivers with
# their hot functions together (Documentation/performance.md, "Program text"; without it they link with
# the default linker and use about 1 MB more memory)
packages=(build-essential cmake libeigen3-dev libvtk9-dev libgtest-dev gnuplot-nox python3 lld)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  if [[ "$status" != *"install ok installed"* ]]; then
    missing+=("$p")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi

if [[ $(id -u) -eq 0 ]]; then
  echo "install-deps: installing ${missing[*]}" >&2
  apt-get update
  DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
else
  echo "install-deps: missing Debian packages: ${missing[*]}" >&2
  echo "run this script again as root, or install them as root with:" >&2
  echo "  apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends ${missing[*]}" >&2
  exit 1
fi
