#!/bin/sh
# `cmake --install` into a temporary prefix, then the installed command run as
# a user runs it: from a folder outside the source tree, PLAUSIBLE_SCENES_DIR
# unset. It must read the installed scenes and goldens, never the source
# tree's (docs/design.md, "Installed"): proved by what only the installed
# copy has (a scene added to its catalogue, a golden taken out of it), and by
# a lone copy of the binary, which must fail and name where it looked.
# The prefix is a temporary folder outside the build tree (a command inside
# the build tree reads the source tree by design), kept when the test fails.
#   install_test.sh CMAKE BUILD_DIR
set -eu
cmake=$1
build=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/plausible-install.XXXXXX")
work=$(cd "$work" && pwd -P)  # as /proc/self/exe names it, links resolved
mkdir -p "$work/user"
prefix=$work/prefix
unset PLAUSIBLE_SCENES_DIR
fail() { echo "install_test: $* (left in $work)" >&2; exit 1; }

"$cmake" --install "$build" --prefix "$prefix" >"$work/install.log"
share=$prefix/share/plausible
for f in bin/plausible share/plausible/scenes/catalog.txt share/plausible/scenes/oscillator.toml \
         share/plausible/golden/oscillator.png share/plausible/golden/oscillator.json \
         share/doc/plausible/README.md share/doc/plausible/docs/design.md; do
  [ -f "$prefix/$f" ] || fail "not installed: $f"
done
cd "$work/user"
plausible=$prefix/bin/plausible

# list and run read the installed scenes: a scene only the installed
# catalogue has is listed and runs.
sed 's/^description = .*/description = "Only in the installed copy."/' "$share/scenes/oscillator.toml" \
  >"$share/scenes/installed-only.toml"
echo "installed-only" >>"$share/scenes/catalog.txt"
"$plausible" list >list.txt
grep -q '^oscillator ' list.txt || fail "list shows no oscillator: $(cat list.txt)"
grep -q '^installed-only *Only in the installed copy' list.txt || fail "list did not read $share/scenes: $(cat list.txt)"
"$plausible" run installed-only --frames 10 --json >run.json || fail "run installed-only failed"
grep -q '"steps"' run.json || fail "run printed no JSON: $(cat run.json)"
"$plausible" run oscillator --frames 10 >/dev/null || fail "run oscillator failed"

# check reads the installed goldens: one passes, one taken out of the
# installed golden/ is missing there (exit 1, the path in the message).
"$plausible" check oscillator --report check >check.txt 2>&1 || fail "check oscillator: $(cat check.txt)"
grep -q '1 passed, 0 failed' check.txt || fail "check oscillator did not pass: $(cat check.txt)"
rm "$share/golden/ballistic.png" "$share/golden/ballistic.json"
status=0
"$plausible" check ballistic --report check >check.txt 2>&1 || status=$?
[ "$status" = 1 ] || fail "check without the installed golden gave exit $status: $(cat check.txt)"
grep -q "no golden $share/golden/ballistic.png" check.txt || fail "check did not read $share/golden: $(cat check.txt)"

# check --golden DIR: goldens for a user's own scene, kept outside the project.
cp "$share/scenes/oscillator.toml" mine.toml
"$plausible" check mine.toml --golden goldens --update missing --report check >check.txt 2>&1 ||
  fail "check --golden --update missing: $(cat check.txt)"
[ -f goldens/mine.png ] && [ -f goldens/mine.json ] || fail "no goldens written in goldens/: $(cat check.txt)"
"$plausible" check mine.toml --golden goldens --report check >check.txt 2>&1 || fail "check --golden: $(cat check.txt)"
grep -q '1 passed, 0 failed' check.txt || fail "check --golden did not pass: $(cat check.txt)"
status=0
"$plausible" check mine.toml --golden no-such-folder >check.txt 2>&1 || status=$?
[ "$status" = 2 ] && grep -q 'no-such-folder: no such folder' check.txt ||
  fail "check --golden with no folder gave exit $status: $(cat check.txt)"

# A copy of the command with no share/plausible beside it fails and says
# where it looked (it does not fall back to the source tree).
mkdir -p "$work/lone/bin"
cp "$plausible" "$work/lone/bin/plausible"
status=0
"$work/lone/bin/plausible" list >lone.txt 2>&1 || status=$?
[ "$status" = 2 ] && grep -q "no $work/lone/share/plausible/scenes/catalog.txt" lone.txt ||
  fail "a lone copy gave exit $status: $(cat lone.txt)"
PLAUSIBLE_SCENES_DIR=$share/scenes "$work/lone/bin/plausible" list | grep -q '^installed-only ' ||
  fail "PLAUSIBLE_SCENES_DIR did not override"
rm -rf "$work"
echo "install_test: list, run and check read the installed share/plausible; check --golden; a lone copy refused"
