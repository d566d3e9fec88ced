#!/bin/sh
# Chipmunk2D 7.0.3 built for release (-O2 -DNDEBUG) from Debian's own source package,
# for make bench-peers (Debian's libchipmunk-dev is built with its debug assertions on).
# Usage: tools/bench-peers/chipmunk-release.sh BUILD_DIR
#   BUILD_DIR/chipmunk-src/      the source package (apt-get source chipmunk), fetched once
#   BUILD_DIR/chipmunk-release/  libchipmunk.a and include/chipmunk/*.h
# Fetching needs root (a deb-src line for the machine's own Debian suite is added to
# apt's sources, in /etc/apt/sources.list.d/ntile-deb-src.*) and the network; with the
# source already fetched, neither. Exit 1 (with the reason) when it cannot be built:
# make bench-peers then falls back to Debian's build.
set -eu
build=${1:?usage: chipmunk-release.sh BUILD_DIR}
cc=${CC:-cc}
src_dir=$build/chipmunk-src
out=$build/chipmunk-release
version=7.0.3
say() { echo "ntile: chipmunk-release: $*" >&2; }

src=$(ls -d "$src_dir"/chipmunk-"$version" 2>/dev/null || true)
if [ -z "$src" ]; then
    if [ "$(id -u)" != 0 ] || ! command -v apt-get >/dev/null 2>&1; then
        say "the source package is not fetched yet ($src_dir) and fetching it needs root:"
        say "  sudo $0 $build"
        exit 1
    fi
    command -v dpkg-source >/dev/null 2>&1 || {
        say "installing dpkg-dev (apt-get source unpacks with dpkg-source)"
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq dpkg-dev >/dev/null || exit 1; }
    if ! apt-cache showsrc chipmunk 2>/dev/null | grep -q "^Version: $version"; then
        # a deb-src line for the suite(s) the machine already uses, from its own sources
        if [ -f /etc/apt/sources.list.d/debian.sources ]; then
            list=/etc/apt/sources.list.d/ntile-deb-src.sources
            sed -n 's/^Types:.*\bdeb\b.*$/Types: deb-src/; /^#/d; p' /etc/apt/sources.list.d/debian.sources >"$list"
        else
            list=/etc/apt/sources.list.d/ntile-deb-src.list
            grep -h '^deb [^ ]*debian' /etc/apt/sources.list 2>/dev/null | sed 's/^deb /deb-src /' >"$list" || true
        fi
        [ -s "$list" ] || { say "no Debian apt source found to derive a deb-src line from"; rm -f "$list"; exit 1; }
        say "added $list (deb-src for $(. /etc/os-release && echo "$VERSION_CODENAME")); apt-get update for it"
        apt-get update -qq -o Dir::Etc::sourcelist="$list" -o Dir::Etc::sourceparts=- \
            -o APT::Get::List-Cleanup=0 || { say "apt-get update failed"; exit 1; }
    fi
    mkdir -p "$src_dir"
    say "apt-get source chipmunk into $src_dir"
    (cd "$src_dir" && apt-get source -qq chipmunk >/dev/null) || { say "apt-get source chipmunk failed"; exit 1; }
    src=$(ls -d "$src_dir"/chipmunk-"$version" 2>/dev/null || true)
    [ -n "$src" ] || { say "the source package is not Chipmunk $version: $(ls "$src_dir")"; exit 1; }
fi

# Build: every src/*.c (cpHastySpace.c too, as Debian's library has it) with -O2 -DNDEBUG.
# (-w: the warnings are Chipmunk's own, not ntile's to fix.)
# Up to date when the library is newer than every source and this script.
lib=$out/libchipmunk.a
if [ -f "$lib" ] && [ -z "$(find "$src/src" "$src/include" "$0" -newer "$lib" -type f 2>/dev/null | head -1)" ]; then
    exit 0
fi
say "building $lib from $src (-O2 -DNDEBUG)"
rm -rf "$out"
mkdir -p "$out/obj" "$out/include"
for c in "$src"/src/*.c; do
    o=$out/obj/$(basename "$c" .c).o
    $cc -std=gnu99 -O2 -DNDEBUG -fPIC -w -I"$src/include" -c "$c" -o "$o" || { say "compiling $c failed"; exit 1; }
done
ar rcs "$lib.tmp" "$out"/obj/*.o && mv "$lib.tmp" "$lib"
cp -R "$src/include/chipmunk" "$out/include/"
echo "-O2 -DNDEBUG -std=gnu99, $($cc --version | head -1), from $(basename "$src") ($(ls "$src_dir"/*.dsc 2>/dev/null | xargs -n1 basename))" >"$out/BUILT"
say "built $lib"
