#!/bin/sh
# make check-install: install into a staging directory (DESTDIR + PREFIX), build the
# embedding example against the installed copy through pkg-config only (never the
# source tree), run it and check its answer, shared and static; check that a program
# compiled with the other NT_DOUBLE setting does not link; build a game-layer program
# through ntile-game.pc on an installed level; run the installed tools on a shipped
# level given by name; then uninstall and check that exactly what install put there
# went away.
# Environment: MAKE, CC, VERSION (expected pkg-config version).
set -u
MAKE=${MAKE:-make}
CC=${CC:-cc}
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAILED: $*"; }
finish() { echo "check-install: $pass passed, $fail failed"; [ "$fail" -eq 0 ]; exit $?; }

tmp=$(mktemp -d "${TMPDIR:-/tmp}/ntile-install-XXXXXX") || exit 2
trap 'rm -rf "$tmp"' EXIT
stage=$tmp/stage
prefix=/opt/ntile
lib=$stage$prefix/lib
inc=$stage$prefix/include
bin=$stage$prefix/bin
levels=$stage$prefix/share/ntile/levels
# Files that were there before: uninstall must leave them, and their directories.
mkdir -p "$lib/pkgconfig" "$inc"
echo keep >"$lib/unrelated.txt"
echo keep >"$lib/pkgconfig/other.pc"
echo keep >"$inc/other.h"

if $MAKE --no-print-directory -s install DESTDIR="$stage" PREFIX="$prefix" >"$tmp/log" 2>&1; then ok; else
    bad "make install"; cat "$tmp/log"; finish; fi

# What install puts there.
for h in include/ntile/*.h; do
    if cmp -s "$h" "$inc/ntile/${h##*/}"; then ok; else bad "header ${h##*/} not installed"; fi
done
[ -f "$lib/libntile.a" ] && ok || bad "libntile.a not installed"
[ -f "$lib/libntile-game.a" ] && ok || bad "libntile-game.a (the game layer, include/ntile/game.h) not installed"
real=$(cd "$lib" && ls libntile.so.*.*.* 2>/dev/null | head -n 1)
[ -n "$real" ] && [ -f "$lib/$real" ] && [ ! -L "$lib/$real" ] && ok || bad "no libntile.so.X.Y.Z"
soname=$(readelf -d "$lib/$real" 2>/dev/null | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
[ "$soname" = libntile.so.0.2 ] && ok || bad "soname is '$soname', want libntile.so.0.2"
[ "$(readlink "$lib/libntile.so.0.2")" = "$real" ] && ok || bad "libntile.so.0.2 does not point to $real"
[ -L "$lib/libntile.so" ] && [ "$(cd "$lib" && readlink -f libntile.so)" = "$(cd "$lib" && readlink -f "$real")" ] && ok ||
    bad "libntile.so does not lead to $real"
[ -f "$lib/pkgconfig/ntile.pc" ] && ok || bad "ntile.pc not installed"
[ -f "$lib/pkgconfig/ntile-game.pc" ] && ok || bad "ntile-game.pc not installed"
for l in levels/*.ntl; do
    if cmp -s "$l" "$levels/${l##*/}"; then ok; else bad "level ${l##*/} not installed in share/ntile/levels"; fi
done
[ -x "$bin/ntile" ] && ok || bad "bin/ntile not installed"

# pkg-config sees only the staged copy: the .pc names the final prefix, the sysroot
# maps it into the staging directory.
PKG_CONFIG_LIBDIR=$lib/pkgconfig
PKG_CONFIG_PATH=$lib/pkgconfig
PKG_CONFIG_SYSROOT_DIR=$stage
export PKG_CONFIG_LIBDIR PKG_CONFIG_PATH PKG_CONFIG_SYSROOT_DIR
if pkg-config --validate ntile 2>"$tmp/log"; then ok; else bad "ntile.pc does not validate"; cat "$tmp/log"; fi
if pkg-config --validate ntile-game 2>"$tmp/log"; then ok; else bad "ntile-game.pc does not validate"; cat "$tmp/log"; fi
v=$(pkg-config --modversion ntile)
[ "$v" = "${VERSION:-$v}" ] && ok || bad "pkg-config version '$v', want '$VERSION'"
cflags=$(pkg-config --cflags ntile) libs=$(pkg-config --libs ntile) static=$(pkg-config --static --libs ntile)
echo "pkg-config --cflags --libs ntile: $cflags $libs"
case " $cflags " in *" -I$inc "*) ok ;; *) bad "cflags '$cflags' lack -I$inc" ;; esac
case " $libs " in *" -L$lib "*"-lntile "*) ok ;; *) bad "libs '$libs' lack -L$lib -lntile" ;; esac
case " $static " in *" -lm "*) ok ;; *) bad "static libs '$static' lack -lm" ;; esac

# Run an example and check its output: $1 = binary, $2 = what, $3 = an awk program
# that exits 0 when the output is right, $4 = what is wrong when it is not.
check_run() {
    if "$1" >"$tmp/out" 2>"$tmp/err"; then ok; else bad "$2: the example failed"; cat "$tmp/err" "$tmp/out"; return; fi
    if awk "$3" "$tmp/out"; then ok; echo "$2: $(tail -n 1 "$tmp/out")"; else bad "$2: $4"; cat "$tmp/out"; fi
}
# The embedding example is a platformer: its player runs down a ramp (floor snap),
# climbs a half-tile step (step-up), rides a lift, jumps to a one-way platform, drops
# through it, jumps a pit and reaches the goal; it says so in its last line, with the
# tick and where it stands. The floor's top is at y = 336, the player's half-height 24:
# on the floor, its centre is at 312. The line is the same in float and double builds.
platformer_done='/^platformer: reached the goal at tick / { found = 1; gsub(/,/, ""); n = $7; y = $9; f = $11; s = $13; u = $16 }
    END { exit !(found && n > 0 && n <= 1500 && y > 311.99 && y < 312.05 && f == 1 && s > 0 && u >= 1) }'
# The README's example drops a box onto a floor whose top is at y = 480; the box's
# half-height is 6: it rests a skin deep, on_floor 1 (a line without on_floor passes it).
box_rests='/^box rests at / { found = 1; x = $4; y = $5; f = NF < 7 ? 1 : $7 }
    END { exit !(found && x > 99.99 && x < 100.01 && y > 473.99 && y < 474.05 && f == 1) }'

# The example, as a user builds it, against the shared library ...
if $CC -std=c11 -Wall -Wextra -Wpedantic -Werror tools/embed-example/embed.c $cflags $libs -o "$tmp/embed" 2>"$tmp/log"; then
    ok
    readelf -d "$tmp/embed" | grep -q 'NEEDED.*\[libntile\.so\.0\.2\]' && ok || bad "the example does not load libntile.so.0.2"
    LD_LIBRARY_PATH=$lib check_run "$tmp/embed" "shared" "$platformer_done" "the player does not reach the goal on the floor"
else bad "building the example against the shared library"; cat "$tmp/log"; fi
# ... and statically (pkg-config --static adds Libs.private).
slibs=$(echo " $static " | sed 's/ -lntile / -Wl,-Bstatic -lntile -Wl,-Bdynamic /')
if $CC -std=c11 -Wall -Wextra -Wpedantic -Werror tools/embed-example/embed.c $cflags $slibs -o "$tmp/embed-static" 2>"$tmp/log"; then
    ok
    readelf -d "$tmp/embed-static" | grep -q 'NEEDED.*libntile' && bad "the static example needs libntile.so" || ok
    check_run "$tmp/embed-static" "static" "$platformer_done" "the player does not reach the goal on the floor"
else bad "building the example against the static library"; cat "$tmp/log"; fi

# The same example compiled with the other NT_DOUBLE setting than the installed
# library's must not link (include/ntile/base.h), shared or static.
case " $cflags " in
*" -DNT_DOUBLE "*) other=-UNT_DOUBLE want=nt_real_float_library ;;
*) other=-DNT_DOUBLE want=nt_real_double_library ;;
esac
for how in shared static; do
    l=$libs
    [ $how = static ] && l=$slibs
    if $CC -std=c11 tools/embed-example/embed.c $cflags $other $l -o "$tmp/mismatch" 2>"$tmp/log"; then
        bad "$how: the example compiled with $other links against the installed library"
    elif grep -q "$want" "$tmp/log"; then ok; else bad "$how: the mismatched link failed without naming $want"; cat "$tmp/log"; fi
done

# The game layer through ntile-game.pc (which requires ntile.pc): a shipped level, read
# from where install put it, played for two seconds.
gcflags=$(pkg-config --cflags ntile-game) glibs=$(pkg-config --libs ntile-game)
case " $glibs " in *" -lntile-game "*"-lntile "*) ok ;; *) bad "ntile-game libs '$glibs' lack -lntile-game before -lntile" ;; esac
cat >"$tmp/game.c" <<'C'
#include <stdio.h>
#include <stdlib.h>
#include <ntile/game.h>
int main(void)
{
    static char text[1 << 20];
    FILE *f = fopen(LEVEL, "rb");
    if (!f) return 1;
    size_t n = fread(text, 1, sizeof text, f);
    fclose(f);
    nt_level *level;
    nt_text_error e;
    if (nt_level_parse(LEVEL, text, n, &level, &e) != NT_OK) return 2;
    nt_game *game;
    nt_game_def def = nt_default_game_def();
    if (nt_game_create(level, &def, &game) != NT_OK) return 3;
    for (int t = 0; t < 80; t++) nt_game_step(game, 0, (nt_real)0.025);
    printf("game ok: %d bodies\n", nt_world_get_body_count(nt_game_get_world(game)));
    nt_game_destroy(game);
    nt_level_destroy(level);
    return 0;
}
C
if $CC -std=c11 -Wall -Wextra -Wpedantic -Werror -DLEVEL="\"$levels/ninja.ntl\"" "$tmp/game.c" $gcflags $glibs \
    -o "$tmp/game" 2>"$tmp/log"; then
    ok
    LD_LIBRARY_PATH=$lib check_run "$tmp/game" "game layer" '/^game ok: [1-9]/ { found = 1 } END { exit !found }' \
        "the game does not run the installed level"
else bad "building a game-layer program through ntile-game.pc"; cat "$tmp/log"; fi

# The installed tools find a shipped level by name, from a directory that has none.
mkdir -p "$tmp/elsewhere"
if (cd "$tmp/elsewhere" && "$bin/ntile" run --level ninja --ticks 40) >"$tmp/out" 2>&1 &&
    grep -q '^tick 40 ' "$tmp/out"; then ok; else bad "installed ntile does not find the level 'ninja'"; cat "$tmp/out"; fi
if (cd "$tmp/elsewhere" && "$bin/ntile" run --level no-such-level --ticks 40) >"$tmp/out" 2>&1; then
    bad "installed ntile runs a level that does not exist"
else grep -q "no-such-level" "$tmp/out" && ok || { bad "the message does not name the missing level"; cat "$tmp/out"; }; fi
if [ -x "$bin/ntile-play" ]; then
    # tour by name; with no level, the default (ninja) among the installed ones
    for args in "tour" ""; do
        if (cd "$tmp/elsewhere" && SDL_VIDEODRIVER=dummy "$bin/ntile-play" $args --frames 2 --screenshot "$tmp/play.png") \
            >"$tmp/out" 2>&1 && [ -s "$tmp/play.png" ]; then ok
        else bad "installed ntile-play does not play '${args:-its default level}'"; cat "$tmp/out"; fi
        rm -f "$tmp/play.png"
    done
else echo "check-install: ntile-play was not built (no SDL2): its level lookup is not checked"; fi

# The README's 20-line example, exactly as printed there (the c block after the marker).
awk '/<!-- make check-install builds this example -->/ { m = 1; next }
     m && /^```c$/ { c = 1; next } c && /^```$/ { exit } c { print }' README.md >"$tmp/readme.c"
if [ ! -s "$tmp/readme.c" ]; then
    bad "README.md: no C example after '<!-- make check-install builds this example -->'"
elif $CC -std=c11 -Wall -Wextra -Wpedantic -Werror "$tmp/readme.c" $cflags $libs -o "$tmp/readme" 2>"$tmp/log"; then
    ok
    LD_LIBRARY_PATH=$lib check_run "$tmp/readme" "README example" "$box_rests" "the box does not rest on the floor"
else bad "building the README's example"; cat "$tmp/log"; fi

# Uninstall: the staged tree holds exactly the files that were there before.
if $MAKE --no-print-directory -s uninstall DESTDIR="$stage" PREFIX="$prefix" >"$tmp/log" 2>&1; then ok; else
    bad "make uninstall"; cat "$tmp/log"; fi
left=$(cd "$stage" && find . ! -type d | sort | tr '\n' ' ')
want="./opt/ntile/include/other.h ./opt/ntile/lib/pkgconfig/other.pc ./opt/ntile/lib/unrelated.txt "
[ "$left" = "$want" ] && ok || bad "after uninstall: '$left', want '$want'"
[ ! -e "$inc/ntile" ] && ok || bad "uninstall left $inc/ntile"
[ ! -e "$stage$prefix/share/ntile" ] && ok || bad "uninstall left $stage$prefix/share/ntile"
finish
