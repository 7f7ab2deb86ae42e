#!/usr/bin/env bash
# apt-install.sh TAG PACKAGE...: install the Debian packages that are missing (sudo when not
# root), saying which under "[TAG]"; the one apt step of scripts/setup.sh and scripts/lint.sh.
set -euo pipefail
tag=$1; shift
missing=()
for p in "$@"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
((${#missing[@]})) || exit 0
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
echo "[$tag] installing apt packages: ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
