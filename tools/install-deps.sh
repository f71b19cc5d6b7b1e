#!/bin/sh
# Installs the Debian packages listed in tools/debian-packages.txt that are
# missing. Idempotent: when dpkg-query reports every package installed, no apt
# command runs at all. Needs root, or sudo without a password prompt.
set -eu

list="$(dirname "$0")/debian-packages.txt"
wanted=$(sed -e 's/#.*//' "$list" | tr -s ' \t' '\n' | grep -v '^$')

missing=""
for pkg in $wanted; do
    status=$(dpkg-query -W -f='${db:Status-Status}' "$pkg" 2>/dev/null || true)
    [ "$status" = "installed" ] || missing="$missing $pkg"
done

if [ -z "$missing" ]; then
    echo "deps: all $(echo $wanted | wc -w) Debian packages are installed"
    exit 0
fi

echo "deps: missing Debian packages:$missing"
if [ "$(id -u)" -eq 0 ]; then
    as_root=""
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    as_root="sudo -n"
else
    echo "deps: error: installing them needs root; run as root, or with sudo set up, or install them yourself:" >&2
    echo "      apt-get install$missing" >&2
    exit 1
fi

export DEBIAN_FRONTEND=noninteractive
$as_root apt-get update -q
# shellcheck disable=SC2086 # word splitting of the package list is intended
$as_root apt-get install -y -q --no-install-recommends $missing
