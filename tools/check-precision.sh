#!/bin/sh
# The link-time check of NT_DOUBLE (include/ntile/base.h): a program compiled with the
# library's own setting links and runs (nt_real_size agrees); one compiled with the
# other setting must fail to link, naming the symbol of its setting. Run by make test.
# Environment: CC, LIB (libntile.a or libntile.so), NT_DOUBLE (the library's setting,
# 0 or 1), SAN (the sanitizer flags the library was built with, if any).
set -u
CC=${CC:-cc}
LIB=${LIB:-build/libntile.a}
NT_DOUBLE=${NT_DOUBLE:-0}
SAN=${SAN:-}
LD_LIBRARY_PATH=$(dirname "$LIB")${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} # for libntile.so
export LD_LIBRARY_PATH
tmp=$(mktemp -d "${TMPDIR:-/tmp}/ntile-precision-XXXXXX") || exit 2
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAILED: $*"; }

cat >"$tmp/p.c" <<'C'
#include <stdio.h>
#include <ntile/ntile.h>
int main(void)
{
    printf("%d\n", nt_real_size());
    return nt_real_size() == (int)sizeof(nt_real) ? 0 : 1;
}
C
if [ "$NT_DOUBLE" = 0 ]; then same= other=-DNT_DOUBLE want=nt_real_double_library size=4
else same=-DNT_DOUBLE other= want=nt_real_float_library size=8; fi

if $CC $SAN -std=c11 -Wall -Wextra -Wpedantic -Werror -Iinclude $same "$tmp/p.c" "$LIB" -lm -o "$tmp/same" 2>"$tmp/log"; then
    ok
    [ "$("$tmp/same")" = $size ] && ok || bad "the program built with the library's setting does not see nt_real_size() = $size"
else bad "a program built with the library's setting ($same) does not link"; cat "$tmp/log"; fi
if $CC $SAN -std=c11 -Wall -Wextra -Wpedantic -Werror -Iinclude $other "$tmp/p.c" "$LIB" -lm -o "$tmp/other" 2>"$tmp/log"; then
    bad "a program built with the other setting (${other:-no -DNT_DOUBLE}) links against $LIB"
else
    grep -q "$want" "$tmp/log" && ok || { bad "the link failed without naming $want"; cat "$tmp/log"; }
fi
echo "check-precision ($LIB): $pass passed, $fail failed"
[ "$fail" -eq 0 ]
