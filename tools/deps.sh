#!/bin/sh
# Make sure the Debian packages a target needs are installed.
# Usage: tools/deps.sh FEATURE...   (features: cc, cxx, cmocka, clang, fuzzer, pkgconfig, sdl2, xvfb,
#                                    valgrind, xmllint, chipmunk, box2d, multilib; tiled: jansson, expat and zlib for the
#                                    Tiled importer of the ntile CLI)
# Installs what is missing with apt-get when run as root; otherwise prints the exact
# command to run and exits 1.
set -u
missing=""
have_header() { # $1 = header, $2 = extra flags
    printf '#include <stdarg.h>\n#include <stddef.h>\n#include <setjmp.h>\n#include <stdint.h>\n#include <%s>\nint main(void){return 0;}\n' "$1" \
        | ${CC:-cc} -x c - -o /dev/null $2 >/dev/null 2>&1
}
for f in "$@"; do
    case "$f" in
    cc) command -v "$(echo "${CC:-cc}" | cut -d" " -f1)" >/dev/null 2>&1 && command -v make >/dev/null 2>&1 || missing="$missing build-essential" ;;
    cmocka) have_header cmocka.h -lcmocka || missing="$missing libcmocka-dev" ;;
    cxx) command -v "${CXX:-g++}" >/dev/null 2>&1 || missing="$missing g++" ;;
    chipmunk) have_header chipmunk/chipmunk.h -lchipmunk || missing="$missing libchipmunk-dev" ;;
    box2d) # a C++ library: try to compile and link against it
        printf '#include <box2d/box2d.h>\nint main(){b2World w(b2Vec2(0,0));return 0;}\n' \
            | ${CXX:-g++} -x c++ - -o /dev/null -lbox2d >/dev/null 2>&1 || missing="$missing libbox2d-dev" ;;
    clang) command -v clang >/dev/null 2>&1 || missing="$missing clang" ;;
    fuzzer) # libFuzzer comes with clang's runtime package, named after clang's major version
        if ! command -v clang >/dev/null 2>&1; then missing="$missing clang"
        elif ! printf 'int LLVMFuzzerTestOneInput(const char *d, unsigned long n){(void)d;(void)n;return 0;}\n' \
                | clang -x c - -fsanitize=fuzzer -o /dev/null >/dev/null 2>&1; then
            missing="$missing libclang-rt-$(clang -dumpversion | cut -d. -f1)-dev"
        fi ;;
    tiled)
        have_header jansson.h -ljansson || missing="$missing libjansson-dev"
        have_header expat.h -lexpat || missing="$missing libexpat1-dev"
        have_header zlib.h -lz || missing="$missing zlib1g-dev" ;;
    pkgconfig) command -v pkg-config >/dev/null 2>&1 || missing="$missing pkg-config" ;;
    sdl2) command -v sdl2-config >/dev/null 2>&1 || missing="$missing libsdl2-dev" ;;
    xvfb) command -v xvfb-run >/dev/null 2>&1 || missing="$missing xvfb"
          command -v xauth >/dev/null 2>&1 || missing="$missing xauth" ;; # xvfb-run needs it (only recommended by xvfb)
    valgrind) command -v valgrind >/dev/null 2>&1 || missing="$missing valgrind" ;;
    xmllint) command -v xmllint >/dev/null 2>&1 || missing="$missing libxml2-utils" ;; # test_run checks JUnit reports
    multilib) # 32-bit x86 programs from gcc (make determinism)
        printf '#include <math.h>\nint main(void){return (int)sqrt(4.0);}\n' \
            | gcc -m32 -x c - -o /dev/null -lm >/dev/null 2>&1 || missing="$missing gcc-multilib" ;;
    *) echo "tools/deps.sh: unknown feature '$f'" >&2; exit 2 ;;
    esac
done
[ -z "$missing" ] && exit 0
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "ntile: installing missing Debian packages:$missing"
    export DEBIAN_FRONTEND=noninteractive
    # make -j may run two of these at once (cmocka, tiled): the second waits for dpkg's lock
    apt-get update -qq && apt-get install -y -qq -o DPkg::Lock::Timeout=600 $missing >/dev/null || {
        echo "ntile: apt-get install failed for:$missing" >&2; exit 1; }
    exit 0
fi
echo "ntile: missing Debian packages:$missing" >&2
echo "ntile: install them with:  sudo apt-get install -y$missing" >&2
exit 1
