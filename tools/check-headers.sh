#!/bin/sh
# make check-headers: every public header compiles on its own (included twice, so the
# include guard is exercised) as C11 with the project's warnings and -Werror, in float
# and double builds, and as C++11. The C++ program also takes the address of a function
# the header declares and is linked against the library: a header without its
# extern "C" block compiles but fails to link (the C++ name is mangled).
# Environment: CC, CXX, CWARN (the project's C warning flags), LIB (libntile.a).
set -u
CC=${CC:-cc}
CXX=${CXX:-g++}
CWARN=${CWARN:--Wall -Wextra -Wpedantic -Wshadow -Wmissing-prototypes}
LIB=${LIB:-build/libntile.a}
GAMELIB=${GAMELIB:-build/libntile-game.a}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/ntile-headers-XXXXXX") || exit 2
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0

# The first non-inline function a header declares (a line "TYPE nt_name(").
probe() {
    grep -E '^[A-Za-z_][A-Za-z0-9_ ]*[ *]nt_[a-z0-9_]+\(' "$1" | grep -vE '^(static|typedef)' | head -n 1 |
        sed -E 's/^.*[ *](nt_[a-z0-9_]+)\(.*$/\1/'
}

check() { # $1 = what, then the command
    what=$1
    shift
    if "$@" >"$tmp/log" 2>&1; then
        pass=$((pass + 1))
    else
        fail=$((fail + 1))
        echo "FAILED: $what"
        sed 's/^/    /' "$tmp/log"
    fi
}

all_probes=""
for h in include/ntile/*.h; do
    [ "$h" = include/ntile/game.h ] && continue # the game layer is not in the umbrella header
    p=$(probe "$h")
    [ -n "$p" ] && all_probes="$all_probes $p"
done

for h in include/ntile/*.h; do
    name=${h#include/}
    printf '#include "%s"\n#include "%s"\nint main(void) { return 0; }\n' "$name" "$name" >"$tmp/c.c"
    check "$name as C11" $CC -std=c11 $CWARN -Werror -ffp-contract=off -Iinclude -c "$tmp/c.c" -o "$tmp/c.o"
    check "$name as C11, NT_DOUBLE" $CC -std=c11 $CWARN -Werror -ffp-contract=off -DNT_DOUBLE -Iinclude -c "$tmp/c.c" -o "$tmp/c.o"
    probes=$(probe "$h")
    [ -n "$probes" ] || probes=$all_probes # the umbrella header: every header's function
    {
        printf '#include "%s"\n#include "%s"\n' "$name" "$name"
        printf 'int main() {\n    int n = 0;\n'
        for p in $probes; do printf '    { decltype(&%s) volatile f = &%s; n += f != nullptr; }\n' "$p" "$p"; done
        printf '    return n > 0 ? 0 : 1;\n}\n'
    } >"$tmp/cxx.cc"
    libs="$LIB"
    [ "$name" = ntile/game.h ] && libs="$GAMELIB $LIB" # its own library, on top of the engine
    check "$name as C++11 (compile and link: extern \"C\")" \
        $CXX -std=c++11 -Wall -Wextra -Wpedantic -Werror -Iinclude "$tmp/cxx.cc" $libs -lm -o "$tmp/cxx"
done
echo "check-headers: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
