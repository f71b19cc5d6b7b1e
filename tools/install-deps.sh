#!/bin/sh
# Installs the Debian packages listed in tools/debian-packages.txt that are
# missing. Idempotent: when dpkg-query reports every package installed (an
# optional one may instead be absent from this release's archive), no apt
# command that changes anything runs at all. Needs root, or sudo without a
# password prompt, only when something is to be installed.
#
# A line of the list is `PACKAGE` or `PACKAGE optional`. A required package the
# archive does not have is an error (exit 1, naming it); an optional one is
# skipped with a note: libosmesa6-dev is in Debian 12 and 13 but not in sid
# (Mesa 25.1 removed OSMesa), and the build then uses EGL.
set -eu

list="$(dirname "$0")/debian-packages.txt"
export LC_ALL=C  # apt-cache's "Candidate:" line, untranslated

# "PACKAGE" or "PACKAGE optional" per line, comments and blank lines dropped.
entries=$(sed -e 's/#.*//' "$list" | awk 'NF > 0 { print $1 ($2 == "optional" ? ":optional" : "") }')

installed() {
    [ "$(dpkg-query -W -f='${db:Status-Status}' "$1" 2>/dev/null || true)" = "installed" ]
}

# True when apt's package lists (as they are now) offer a version of it.
in_archive() {
    candidate=$(apt-cache policy "$1" 2>/dev/null | sed -n 's/^ *Candidate: *//p')
    [ -n "$candidate" ] && [ "$candidate" != "(none)" ]
}

missing_required=""
missing_optional=""
for entry in $entries; do
    pkg=${entry%:optional}
    installed "$pkg" && continue
    if [ "$pkg" = "$entry" ]; then missing_required="$missing_required $pkg"; else missing_optional="$missing_optional $pkg"; fi
done

# Optional packages the archive lacks, going by the lists as they are (no apt
# update): skipped. Required ones are judged after an update, below.
skip_absent_optional() {
    keep=""
    for pkg in $missing_optional; do
        if in_archive "$pkg"; then keep="$keep $pkg"; else echo "deps: optional $pkg is not in this release's archive; skipped"; fi
    done
    missing_optional=$keep
}

if [ -z "$missing_required" ]; then
    skip_absent_optional
    if [ -z "$missing_optional" ]; then
        echo "deps: all $(echo "$entries" | grep -vc ':optional$') required Debian packages are installed"
        exit 0
    fi
fi

echo "deps: missing Debian packages:$missing_required$missing_optional"
if [ "$(id -u)" -eq 0 ]; then
    as_root=""
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    as_root="sudo -n"
else
    echo "deps: error: installing them needs root; run as root, or with sudo set up, or install them yourself:" >&2
    echo "      apt-get install$missing_required$missing_optional" >&2
    exit 1
fi

export DEBIAN_FRONTEND=noninteractive
$as_root apt-get update -q

unknown=""
for pkg in $missing_required; do
    in_archive "$pkg" || unknown="$unknown $pkg"
done
if [ -n "$unknown" ]; then
    echo "deps: error: required packages not in this release's archive:$unknown" >&2
    echo "      (tools/debian-packages.txt lists Debian 12 names; mark a package optional there only if the build works without it)" >&2
    exit 1
fi
skip_absent_optional

# shellcheck disable=SC2086 # word splitting of the package list is intended
$as_root apt-get install -y -q --no-install-recommends $missing_required $missing_optional
