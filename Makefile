# ntile — one Makefile for the library, the tools and the tests.
#
#   make                 libraries (engine static + shared, game layer static) and the
#                        ntile CLI, in build/
#   make lib / make cli  the libraries alone / the ntile CLI alone
#   make help            this list
#   make test            build and run every test (and the link-time NT_DOUBLE check)
#   make valgrind        the whole test suite under valgrind's memcheck
#   make determinism     golden hashes: gcc and clang, -O0/-O2/-O3, float and double
#                        (and gcc -m32 when gcc-multilib is installable)
#   make fuzz [FUZZ_SECONDS=60]  every libFuzzer harness in tests/fuzz, in turn
#   make soak            the long soak: rain checked after every step
#   make screenshot      a frame of the playground, for the README
#   make clean           remove build/
#   make asan            the whole test suite under AddressSanitizer + UBSan
#   make play            the SDL2 playground on the default level (installs libsdl2-dev
#                        when missing and root; `make` builds build/ntile-play whenever
#                        SDL2's development files are there, and skips it otherwise)
#   make run             the headless alternative: replay the default level
#   make play-bin        build build/ntile-play without running it (make play runs it)
#   make deps-cc / deps-test / deps-cxx / deps-pkgconfig / deps-tiled / deps-peers
#                        install the Debian packages that step needs, when missing and root
#   make NT_DOUBLE=1 …   everything with double as the scalar type
#   make CC=clang OPT=-O3 …  any compiler / optimisation level
#   make install [PREFIX=/usr/local] [DESTDIR=]   headers, libraries, ntile.pc and
#                        ntile-game.pc, the tools make built, the shipped levels
#   make uninstall       remove what install put there (same PREFIX and DESTDIR)
#   make check-install   install into a temporary DESTDIR, build and run the embedding
#                        example through pkg-config, uninstall
#   make check-headers   each public header alone as C11 (-Werror) and as C++11
#   make sheet           regenerate tools/ntile/sheet.svg (the answer key shown in the README)
#   make tiles           regenerate src/tile_tables.c (the tile tables) with tools/tilegen
#   make bench           the world scenes: ns per body-step and error metrics, scaling,
#                        character moves against a particles body-step
#   make bench-instructions  instructions per body-step inside nt_world_step (callgrind)
#   make bench-sweep     run time against error: dt, substeps, iterations, friction model,
#                        float and double (CSV + SVG in build/sweep/)
#   make bench-peers     the same scenes in Chipmunk2D 7 and Box2D 2.4 (Debian's
#                        libbox2d-dev, installed when missing). CHIPMUNK=release (the
#                        default when it can be built): Chipmunk 7.0.3 built -O2 -DNDEBUG
#                        from Debian's source package (apt-get source, fetched once as
#                        root into build/chipmunk-src/; tools/bench-peers/chipmunk-release.sh);
#                        otherwise, or with CHIPMUNK=debian, Debian's libchipmunk-dev,
#                        which is built with its debug assertions on (slower)
#
# Replays must be bit-identical across optimisation levels and compilers, so the
# floating-point flags are fixed: -ffp-contract=off always, never -ffast-math.

CC ?= cc
OPT ?= -O2
NT_DOUBLE ?= 0
BUILD ?= build
SAN ?=
CI ?=

WARN := -Wall -Wextra -Wpedantic -Wshadow -Wmissing-prototypes
ifeq ($(CI),true)
WARN += -Werror
endif
DEFS :=
ifneq ($(NT_DOUBLE),0)
DEFS += -DNT_DOUBLE
endif
# -fno-semantic-interposition: the library's own calls may be inlined although it
# is built position-independent (nobody interposes ntile's symbols).
# -fno-math-errno: sqrt is one instruction, without a check for negative inputs
# (ntile never reads errno; the results are the same bits).
# 32-bit x86: x87 arithmetic keeps excess precision (results differ from every other
# target, replays diverge): SSE2 arithmetic instead. src/core_internal.h refuses to compile with
# excess precision (__FLT_EVAL_METHOD__ != 0).
X86_32 := $(shell printf '' | $(CC) $(CFLAGS) -dM -E -x c - 2>/dev/null | grep -c '__i386__ 1')
ifeq ($(X86_32),1)
DEFS += -msse2 -mfpmath=sse
endif
CFLAGS_ALL := -std=c11 $(OPT) $(SAN) $(WARN) -ffp-contract=off -fno-math-errno -fPIC -fno-semantic-interposition \
              -Iinclude $(DEFS) $(CFLAGS)
LDFLAGS_ALL := $(SAN) $(LDFLAGS)
LIBS := -lm

# Objects live in a directory per configuration; linked artefacts are rebuilt
# whenever the configuration changes (build/.config holds the last one).
CONFIG := $(CC) $(CFLAGS_ALL) $(LDFLAGS_ALL)
CONFIG_ID := $(shell printf '%s' '$(CONFIG)' | cksum | cut -d' ' -f1)
OBJ := $(BUILD)/obj/$(CONFIG_ID)
STAMP := $(BUILD)/.config
$(shell mkdir -p $(BUILD); if [ "$$(cat $(STAMP) 2>/dev/null)" != '$(CONFIG)' ]; then printf '%s\n' '$(CONFIG)' > $(STAMP); fi)

SOVERSION := 0.2
SOFULL := 0.2.0

LIB_SRC := $(wildcard src/*.c)
LIB_OBJ := $(LIB_SRC:%.c=$(OBJ)/%.o)
# The game layer (player, level objects, replay runner): its own static library,
# never part of the engine's.
GAME_SRC := $(wildcard src/game/*.c)
GAME_OBJ := $(GAME_SRC:%.c=$(OBJ)/%.o)
GAME_LIB := $(BUILD)/libntile-game.a
CLI_SRC := $(wildcard tools/ntile/*.c)
CLI_OBJ := $(CLI_SRC:%.c=$(OBJ)/%.o)
# The Tiled importer (ntile convert tiled): CLI side only, it reads files and needs
# Debian's jansson (JSON), expat (XML) and zlib; never part of the engine library.
TILED_SRC := $(wildcard tools/tiled/*.c)
TILED_OBJ := $(TILED_SRC:%.c=$(OBJ)/%.o)
TILED_LIBS := -ljansson -lexpat -lz
TEST_SRC := $(wildcard tests/test_*.c)
TEST_BIN := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)
TEST_LIB_SRC := $(filter-out $(TEST_SRC),$(wildcard tests/*.c))
TEST_LIB_OBJ := $(TEST_LIB_SRC:%.c=$(OBJ)/%.o)

# The SDL2 playground (tools/ntile-play): a program beside the libraries, never part
# of them. Built by `make` only when SDL2's development files are installed
# (sdl2-config); everything else builds without SDL. Its test (tests/test_play.c)
# skips with a message when it was not built.
SDL_CONFIG ?= sdl2-config
HAVE_SDL := $(shell $(SDL_CONFIG) --cflags >/dev/null 2>&1 && echo 1)
PLAY_SRC := $(wildcard tools/ntile-play/*.c)
PLAY_OBJ := $(PLAY_SRC:%.c=$(OBJ)/%.o)
PLAY_BIN := $(BUILD)/ntile-play
ifeq ($(HAVE_SDL),1)
# -isystem: SDL's own headers are not held to the project's warnings.
SDL_CFLAGS := $(patsubst -I%,-isystem %,$(shell $(SDL_CONFIG) --cflags))
SDL_LIBS := $(shell $(SDL_CONFIG) --libs)
PLAY_TARGET := $(PLAY_BIN)
endif

.PHONY: all help lib cli play play-bin screenshot test asan valgrind determinism fuzz soak run clean deps-cc \
        deps-test deps-cxx deps-pkgconfig deps-tiled install uninstall check-install check-headers sheet \
        bench bench-instructions bench-sweep bench-peers deps-peers tiles FORCE
.DEFAULT_GOAL := all
# Keep objects of tests (make would delete them as intermediates).
.SECONDARY:

all: lib cli $(PLAY_TARGET)
lib: $(BUILD)/libntile.a $(BUILD)/libntile.so $(GAME_LIB)
cli: $(BUILD)/ntile

deps-cc:
	@tools/deps.sh cc
deps-test:
	@tools/deps.sh cc cmocka xmllint
deps-cxx:
	@tools/deps.sh cc cxx
deps-pkgconfig:
	@tools/deps.sh cc pkgconfig
deps-tiled:
	@tools/deps.sh cc tiled

$(OBJ)/%.o: %.c | deps-cc
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) -MMD -MP -c $< -o $@

$(OBJ)/tools/tiled/%.o: tools/tiled/%.c | deps-tiled
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) -MMD -MP -c $< -o $@

$(BUILD)/libntile.a: $(LIB_OBJ) $(STAMP)
	@rm -f $@
	ar rcs $@ $(LIB_OBJ)

$(BUILD)/libntile.so.$(SOFULL): $(LIB_OBJ) $(STAMP)
	$(CC) -shared -Wl,-soname,libntile.so.$(SOVERSION) $(LDFLAGS_ALL) -o $@ $(LIB_OBJ) $(LIBS)

$(BUILD)/libntile.so: $(BUILD)/libntile.so.$(SOFULL)
	ln -sf libntile.so.$(SOFULL) $(BUILD)/libntile.so.$(SOVERSION)
	ln -sf libntile.so.$(SOFULL) $@

$(GAME_LIB): $(GAME_OBJ) $(STAMP)
	@rm -f $@
	ar rcs $@ $(GAME_OBJ)

$(BUILD)/ntile: $(CLI_OBJ) $(TILED_OBJ) $(GAME_LIB) $(BUILD)/libntile.a | deps-tiled
	$(CC) $(LDFLAGS_ALL) -o $@ $(CLI_OBJ) $(TILED_OBJ) $(GAME_LIB) $(BUILD)/libntile.a $(TILED_LIBS) $(LIBS)

$(OBJ)/tools/ntile-play/%.o: tools/ntile-play/%.c | deps-cc
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) $(SDL_CFLAGS) -MMD -MP -c $< -o $@

$(PLAY_BIN): $(PLAY_OBJ) $(GAME_LIB) $(BUILD)/libntile.a
	$(CC) $(LDFLAGS_ALL) -o $@ $(PLAY_OBJ) $(GAME_LIB) $(BUILD)/libntile.a $(SDL_LIBS) $(LIBS)

# tilegen: the tile tables (src/tile_tables.c) from the canonical shapes; `make tiles`
# rewrites the file, tests/test_tilegen.c checks that it is the generator's output.
TILEGEN_OBJ := $(OBJ)/tools/tilegen/tilegen.o
$(BUILD)/tilegen: $(TILEGEN_OBJ) $(OBJ)/tools/tilegen/main.o
	$(CC) $(LDFLAGS_ALL) -o $@ $^ $(LIBS)

tiles: $(BUILD)/tilegen
	$(BUILD)/tilegen src/tile_tables.c.new && mv src/tile_tables.c.new src/tile_tables.c

# replay-check: replays and their hashes with only the libraries and libc (make
# determinism's 32-bit x86 build, where Tiled's and cmocka's libraries are missing).
$(BUILD)/replay-check: $(OBJ)/tools/replay-check/main.o $(GAME_LIB) $(BUILD)/libntile.a
	$(CC) $(LDFLAGS_ALL) -o $@ $< $(GAME_LIB) $(BUILD)/libntile.a $(LIBS)

# Tests: one cmocka binary per tests/test_*.c, linked with the shared test helpers
# (test_bench also with the benchmark's metric, scene, outline, plot and character-scene code;
# test_tilegen with the tile tables' generator; test_tiled with the Tiled importer).
TEST_EXTRA_OBJ = $(if $(filter test_bench,$*),$(addprefix $(OBJ)/tools/ntile/,scene.o metrics.o plot.o bench_common.o geometry.o \
                 bench_character.o engine_ntile.o bench_run.o)) $(if $(filter test_tilegen,$*),$(TILEGEN_OBJ))
.SECONDEXPANSION:
$(BUILD)/tests/%: $(OBJ)/tests/%.o $(TEST_LIB_OBJ) $$(TEST_EXTRA_OBJ) $(GAME_LIB) $(BUILD)/libntile.a | deps-test
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS_ALL) -o $@ $< $(TEST_LIB_OBJ) $(TEST_EXTRA_OBJ) $(TEST_EXTRA) $(GAME_LIB) $(BUILD)/libntile.a -lcmocka $(TEST_EXTRA_LIBS) $(LIBS)

$(BUILD)/tests/test_tiled: $(TILED_OBJ)
$(BUILD)/tests/test_tiled: TEST_EXTRA = $(TILED_OBJ)
$(BUILD)/tests/test_tiled: TEST_EXTRA_LIBS = $(TILED_LIBS)

$(OBJ)/tests/%.o: tests/%.c | deps-test
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) -Isrc -Itools -Itools/ntile -MMD -MP -c $< -o $@

# make test: every test program, then the link-time NT_DOUBLE check (tools/check-precision.sh)
# against the static and the shared library.
test: deps-test $(TEST_BIN) $(BUILD)/ntile $(PLAY_TARGET) $(BUILD)/libntile.so
	@pass=0; fail=0; for t in $(TEST_BIN); do \
	  echo "== $$t"; if NTILE=$(BUILD)/ntile NTILE_PLAY=$(PLAY_TARGET) $$t; then pass=$$((pass+1)); else fail=$$((fail+1)); echo "FAILED: $$t"; fi; \
	done; \
	echo "test suites: $$pass passed, $$fail failed"; [ $$fail -eq 0 ]
	@for l in $(BUILD)/libntile.a $(BUILD)/libntile.so; do \
	  CC='$(CC)' SAN='$(SAN)' NT_DOUBLE='$(NT_DOUBLE)' LIB=$$l tools/check-precision.sh || exit 1; done

BUILD_ASAN ?= build/asan
asan:
	@$(MAKE) --no-print-directory BUILD=$(BUILD_ASAN) OPT="-O1 -g" \
	  SAN="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer" test

# Every test under valgrind memcheck (children too: test_query runs the CLI; not
# xmllint, which test_run runs on JUnit reports): any error or leak fails.
BUILD_VG ?= build/valgrind
VALGRIND := valgrind --quiet --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite,indirect \
            --show-leak-kinds=definite,indirect --trace-children=yes --trace-children-skip='*/xmllint'
valgrind:
	@tools/deps.sh cc cmocka valgrind xmllint
	@$(MAKE) --no-print-directory BUILD=$(BUILD_VG) OPT="-O1 -g" $(TEST_BIN:$(BUILD)/%=$(BUILD_VG)/%) $(BUILD_VG)/ntile \
	  $(if $(PLAY_TARGET),$(BUILD_VG)/ntile-play)
	@pass=0; fail=0; for t in $(TEST_BIN:$(BUILD)/%=$(BUILD_VG)/%); do \
	  echo "== valgrind $$t"; if NTILE=$(BUILD_VG)/ntile NTILE_PLAY=$(if $(PLAY_TARGET),$(BUILD_VG)/ntile-play) \
	    $(VALGRIND) $$t >$$t.vg.log 2>&1; then pass=$$((pass+1)); \
	  else fail=$$((fail+1)); tail -30 $$t.vg.log; echo "FAILED: $$t"; fi; \
	done; echo "valgrind: $$pass passed, $$fail failed"; [ $$fail -eq 0 ]

# The golden world hashes (test_world, and test_character's scripted run) and every replay's hashes (tests/replays/*.ntr,
# one per scalar type) must come out of gcc and clang at -O0, -O2 and -O3, in both
# scalar builds: each configuration is built and checked against the same goldens. Then
# 32-bit x86 with gcc -m32 (SSE2 arithmetic, see X86_32): the replays' hashes, through
# replay-check, when gcc-multilib is installed or installable (skipped with a message
# otherwise).
DET_CCS ?= gcc clang
DET_OPTS ?= -O0 -O2 -O3
determinism:
	@set -e; for cc in $(DET_CCS); do for o in $(DET_OPTS); do for d in 0 1; do \
	  b=build/det/$$cc$$o-$$d; \
	  $(MAKE) --no-print-directory -s BUILD=$$b CC=$$cc OPT=$$o NT_DOUBLE=$$d $$b/tests/test_world $$b/tests/test_character $$b/ntile >/dev/null; \
	  printf '%-6s %-4s %-6s ' $$cc $$o $$( [ $$d = 1 ] && echo double || echo float ); \
	  for t in test_world test_character; do \
	    $$b/tests/$$t > $$b/$$t.log 2>&1 || { echo FAILED; cat $$b/$$t.log; exit 1; }; \
	    printf '%s, ' "$$(grep 'golden hash' $$b/$$t.log)"; \
	  done; \
	  $$b/ntile run tests/replays/*.ntr > $$b/replays.log 2>&1 || { echo "replays FAILED"; cat $$b/replays.log; exit 1; }; \
	  tail -1 $$b/replays.log; \
	done; done; done; \
	if tools/deps.sh multilib >/dev/null 2>&1; then for d in 0 1; do for o in -O0 -O2; do \
	  b=build/det/gcc-m32$$o-$$d; \
	  $(MAKE) --no-print-directory -s BUILD=$$b CC="gcc -m32" OPT=$$o NT_DOUBLE=$$d $$b/replay-check >/dev/null; \
	  printf '%-6s %-4s %-6s ' gcc-m32 $$o $$( [ $$d = 1 ] && echo double || echo float ); \
	  $$b/replay-check tests/replays/*.ntr > $$b/replays.log 2>&1 || { echo "replays FAILED"; cat $$b/replays.log; exit 1; }; \
	  tail -1 $$b/replays.log; \
	done; done; else echo "determinism: 32-bit x86 (gcc -m32) skipped: gcc-multilib is not installed and could not be (tools/deps.sh multilib)"; fi

# libFuzzer harnesses (tests/fuzz/fuzz_*.c), built with clang and run FUZZ_SECONDS each
# on their committed seed corpus (tests/fuzz/corpus/NAME); new inputs go to a scratch
# corpus in build/fuzz. Any crash, leak, sanitizer report or timeout fails the target.
FUZZ_SECONDS ?= 60
FUZZ_CFLAGS := -std=c11 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
               -ffp-contract=off -Iinclude -Itests -Itools $(DEFS) $(WARN)
FUZZ_NAMES := $(patsubst tests/fuzz/fuzz_%.c,%,$(wildcard tests/fuzz/fuzz_*.c))
FUZZ_EXTRA_query := tools/ntile/query.c
fuzz:
	@tools/deps.sh clang fuzzer tiled
	@mkdir -p build/fuzz
	@set -e; for n in $(FUZZ_NAMES); do \
	  extra=""; libs=""; [ "$$n" = query ] && extra="$(FUZZ_EXTRA_query)"; \
	  [ "$$n" = tiled ] && { extra="$(TILED_SRC)"; libs="$(TILED_LIBS)"; }; \
	  clang $(FUZZ_CFLAGS) tests/fuzz/fuzz_$$n.c $$extra $(LIB_SRC) $$libs -lm -o build/fuzz/fuzz_$$n; \
	  mkdir -p build/fuzz/work_$$n tests/fuzz/corpus/$$n; \
	  echo "== fuzz $$n ($(FUZZ_SECONDS) s)"; \
	  build/fuzz/fuzz_$$n -max_total_time=$(FUZZ_SECONDS) -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
	    -artifact_prefix=build/fuzz/crash_$$n- build/fuzz/work_$$n tests/fuzz/corpus/$$n 2>build/fuzz/$$n.log \
	    || { tail -40 build/fuzz/$$n.log; echo "fuzz $$n: FAILED (inputs in build/fuzz/crash_$$n-*)"; exit 1; }; \
	  grep -E "stat::number_of_executed_units|stat::peak_rss" build/fuzz/$$n.log | tr '\n' ' '; echo; \
	done

# The long soak: the rain scene checked after every step (`ntile soak`; a 10,000-step
# version runs in make test). Takes tens of minutes at the defaults.
SOAK_STEPS ?= 1000000
SOAK_BODIES ?= 10000
soak: $(BUILD)/ntile
	$(BUILD)/ntile soak --steps $(SOAK_STEPS) --bodies $(SOAK_BODIES)

# ---- benchmarks: figures measured on the machine that runs them (RUNS >= 5) ----
RUNS ?= 5
BENCH_SCENES ?= rain particles giants sparse pile asleep slide bounce gas incline flight rest tunnel
bench: $(BUILD)/ntile
	$(BUILD)/ntile bench world $(BENCH_SCENES) --runs $(RUNS)
	$(BUILD)/ntile bench scaling --runs $(RUNS)
	$(BUILD)/ntile bench character --runs $(RUNS)

# The targets, from the comment at the top of this file.
help:
	@sed -n '/^#   make/,/^#$$/p' Makefile | sed 's/^#//'

# Instructions per body-step inside nt_world_step (callgrind), against the step's
# targets: tools/bench-instructions.sh (prints a note and measures nothing without valgrind).
bench-instructions: $(BUILD)/ntile
	@sh tools/bench-instructions.sh $(BUILD)/ntile

# The sweep needs both scalar types: each binary measures its own points, then the
# float one merges the CSVs, finds the Pareto front and draws the SVG.
SWEEP_DIR ?= $(BUILD)/sweep
bench-sweep: $(BUILD)/ntile
	@$(MAKE) --no-print-directory NT_DOUBLE=1 BUILD=$(BUILD)/double-bench $(BUILD)/double-bench/ntile
	@mkdir -p $(SWEEP_DIR)
	$(BUILD)/ntile bench sweep --runs $(RUNS) --out $(SWEEP_DIR)/float.csv
	$(BUILD)/double-bench/ntile bench sweep --runs $(RUNS) --out $(SWEEP_DIR)/double.csv
	$(BUILD)/ntile bench plot $(SWEEP_DIR)/float.csv $(SWEEP_DIR)/double.csv --out $(SWEEP_DIR)/sweep

# Peers: C for everything but the one C++ shim Box2D 2.4 needs (compiled with CXX).
CXX ?= g++
# Chipmunk: CHIPMUNK=release links $(BUILD)/chipmunk-release/libchipmunk.a (7.0.3 from
# Debian's source package, -O2 -DNDEBUG: tools/bench-peers/chipmunk-release.sh, which
# fetches the source once, as root); CHIPMUNK=debian links Debian's libchipmunk-dev
# (debug assertions on). CHIPMUNK=auto (the default): make bench-peers tries the release
# build and falls back to Debian's with a notice; other targets take the release build
# when it is already there. Only chipmunk.c depends on the choice (its object is named
# after it) and build/bench-peers is relinked when the choice changes.
CHIPMUNK ?= auto
CHIPMUNK_RELEASE := $(BUILD)/chipmunk-release
CHIPMUNK_USE := $(if $(filter auto,$(CHIPMUNK)),$(if $(wildcard $(CHIPMUNK_RELEASE)/libchipmunk.a),release,debian),$(CHIPMUNK))
ifeq ($(CHIPMUNK_USE),release)
CHIPMUNK_CFLAGS := -I$(CHIPMUNK_RELEASE)/include -DPEERS_CHIPMUNK_RELEASE
CHIPMUNK_LIBS := $(CHIPMUNK_RELEASE)/libchipmunk.a
CHIPMUNK_PREREQ := $(CHIPMUNK_RELEASE)/libchipmunk.a
CHIPMUNK_DEP :=
else ifeq ($(CHIPMUNK_USE),debian)
CHIPMUNK_CFLAGS :=
CHIPMUNK_LIBS := -lchipmunk
CHIPMUNK_PREREQ :=
CHIPMUNK_DEP := chipmunk
else
$(error CHIPMUNK must be release, debian or auto (not '$(CHIPMUNK)'))
endif
PEER_SRC := $(filter-out tools/bench-peers/chipmunk.c,$(wildcard tools/bench-peers/*.c))
PEER_OBJ := $(PEER_SRC:%.c=$(OBJ)/%.o) $(OBJ)/tools/bench-peers/chipmunk-$(CHIPMUNK_USE).o \
            $(OBJ)/tools/bench-peers/box2d_shim.o
BENCH_SHARED_OBJ := $(addprefix $(OBJ)/tools/ntile/,scene.o metrics.o engine_ntile.o bench_run.o bench_common.o geometry.o)
deps-peers:
	@tools/deps.sh cc cxx $(CHIPMUNK_DEP) box2d

$(CHIPMUNK_RELEASE)/libchipmunk.a: tools/bench-peers/chipmunk-release.sh
	@CC="$(CC)" sh tools/bench-peers/chipmunk-release.sh $(BUILD)

$(OBJ)/tools/bench-peers/chipmunk-$(CHIPMUNK_USE).o: tools/bench-peers/chipmunk.c $(CHIPMUNK_PREREQ) | deps-peers
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) $(CHIPMUNK_CFLAGS) -Itools/ntile -MMD -MP -c $< -o $@

$(OBJ)/tools/bench-peers/%.o: tools/bench-peers/%.c | deps-peers
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) -Itools/ntile -MMD -MP -c $< -o $@

$(OBJ)/tools/bench-peers/box2d_shim.o: tools/bench-peers/box2d_shim.cpp | deps-peers
	@mkdir -p $(dir $@)
	$(CXX) -std=c++11 $(OPT) $(filter-out -Wmissing-prototypes,$(WARN)) -ffp-contract=off -MMD -MP -c $< -o $@

# The Chipmunk build/bench-peers was last linked with, rewritten only when it changes.
$(BUILD)/bench-peers.chipmunk: FORCE
	@mkdir -p $(dir $@)
	@[ "$$(cat $@ 2>/dev/null)" = "$(CHIPMUNK_USE)" ] || echo "$(CHIPMUNK_USE)" >$@

$(BUILD)/bench-peers: $(PEER_OBJ) $(BENCH_SHARED_OBJ) $(BUILD)/libntile.a $(BUILD)/bench-peers.chipmunk
	$(CXX) $(LDFLAGS_ALL) -o $@ $(PEER_OBJ) $(BENCH_SHARED_OBJ) $(BUILD)/libntile.a $(CHIPMUNK_LIBS) -lbox2d $(LIBS)

bench-peers:
	@mode=$(CHIPMUNK); \
	if [ "$$mode" = auto ]; then \
	  if CC="$(CC)" sh tools/bench-peers/chipmunk-release.sh $(BUILD); then mode=release; else mode=debian; \
	    echo "ntile: notice: no release build of Chipmunk (above); comparing against Debian's libchipmunk-dev," \
	         "which is built with its debug assertions on (slower than a release build)"; fi; \
	fi; \
	$(MAKE) --no-print-directory CHIPMUNK=$$mode $(BUILD)/bench-peers
	$(BUILD)/bench-peers --runs $(RUNS)

FORCE:

# The quick start: the playground on the default level. SDL2 is installed first when
# missing (as root; otherwise the apt-get command is printed), then make runs again so
# that it sees sdl2-config. PLAY_ARGS: more arguments (a level, --gizmos ...).
PLAY_ARGS ?= levels/ninja.ntl
# Without a display (no DISPLAY or WAYLAND_DISPLAY, no SDL_VIDEODRIVER chosen) the
# playground cannot open its window: it then plays the default level's replay
# headless, saves its last frame to build/play.png, and the replay is checked.
play:
	@tools/deps.sh cc sdl2
	@$(MAKE) --no-print-directory play-bin
	@if [ -z "$$DISPLAY$$WAYLAND_DISPLAY$$SDL_VIDEODRIVER" ]; then \
	  echo "ntile: no display: playing tests/replays/ninja.ntr headless instead (frame in $(BUILD)/play.png)"; \
	  SDL_VIDEODRIVER=dummy $(BUILD)/ntile-play --replay tests/replays/ninja.ntr --frames 620 \
	    --screenshot $(BUILD)/play.png && $(BUILD)/ntile run tests/replays/ninja.ntr; \
	else $(BUILD)/ntile-play $(PLAY_ARGS); fi
play-bin: lib cli
	@[ "$(HAVE_SDL)" = 1 ] || { echo "ntile: SDL2 development files not found (sdl2-config): tools/deps.sh sdl2" >&2; exit 1; }
	@$(MAKE) --no-print-directory $(PLAY_BIN)

# The README's screenshot, made by the playground itself (no display needed).
screenshot: play-bin
	SDL_VIDEODRIVER=dummy $(BUILD)/ntile-play --replay tests/replays/ninja.ntr --frames 26 --size 1200x720 \
	  --gizmos edges,grid,velocities,split,contacts,rays --mouse 520 560 --screenshot tools/ntile-play/screenshot.png

# The headless alternative: replay the default level.
run: $(BUILD)/ntile
	$(BUILD)/ntile run tests/replays/ninja.ntr

# ---------------------------------------------------------------- install

PREFIX ?= /usr/local
DESTDIR ?=
LIBDIR ?= $(PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
PKGCONFIGDIR ?= $(LIBDIR)/pkgconfig
BINDIR ?= $(PREFIX)/bin
# The shipped levels: the tools look a level name up in ../share/ntile/levels from
# their own directory (tools/common/levels.h), so BINDIR and LEVELSDIR stay side by side.
LEVELSDIR := $(PREFIX)/share/ntile/levels
HEADERS := $(wildcard include/ntile/*.h)
LEVELS := $(wildcard levels/*.ntl)
TOOLS_BUILT := $(BUILD)/ntile $(PLAY_TARGET)
# The version users see is the one the headers announce.
VERSION := $(shell awk '$$2 ~ /^NT_VERSION_(MAJOR|MINOR|PATCH)$$/ { v = v (v == "" ? "" : ".") $$3 } END { print v }' \
             include/ntile/base.h)
# ntile.pc: paths under PREFIX are written relative to ${prefix}, so that pkg-config's
# sysroot and prefix redefinition work; a library built with NT_DOUBLE=1 needs its
# users to define NT_DOUBLE too. ntile-game.pc requires ntile.pc; the game library is
# static only, so its own libm is in Libs.
PC_LIBDIR = $(patsubst $(PREFIX)/%,$${prefix}/%,$(LIBDIR))
PC_INCLUDEDIR = $(patsubst $(PREFIX)/%,$${prefix}/%,$(INCLUDEDIR))
PC_CFLAGS = -I$${includedir}$(if $(filter-out 0,$(NT_DOUBLE)), -DNT_DOUBLE)

install: all
	install -d '$(DESTDIR)$(INCLUDEDIR)/ntile' '$(DESTDIR)$(LIBDIR)' '$(DESTDIR)$(PKGCONFIGDIR)' '$(DESTDIR)$(BINDIR)' \
	  '$(DESTDIR)$(LEVELSDIR)'
	install -m 755 $(TOOLS_BUILT) '$(DESTDIR)$(BINDIR)/'
	install -m 644 $(LEVELS) '$(DESTDIR)$(LEVELSDIR)/'
	install -m 644 $(HEADERS) '$(DESTDIR)$(INCLUDEDIR)/ntile/'
	install -m 644 $(BUILD)/libntile.a '$(DESTDIR)$(LIBDIR)/libntile.a'
	install -m 644 $(GAME_LIB) '$(DESTDIR)$(LIBDIR)/libntile-game.a'
	install -m 755 $(BUILD)/libntile.so.$(SOFULL) '$(DESTDIR)$(LIBDIR)/libntile.so.$(SOFULL)'
	ln -sf libntile.so.$(SOFULL) '$(DESTDIR)$(LIBDIR)/libntile.so.$(SOVERSION)'
	ln -sf libntile.so.$(SOVERSION) '$(DESTDIR)$(LIBDIR)/libntile.so'
	printf '%s\n' 'prefix=$(PREFIX)' 'libdir=$(PC_LIBDIR)' 'includedir=$(PC_INCLUDEDIR)' '' \
	  'Name: ntile' \
	  'Description: Deterministic 2D collision engine in the style of N: tile map, exact projections, world of boxes and circles' \
	  'Version: $(VERSION)' 'Cflags: $(PC_CFLAGS)' 'Libs: -L$${libdir} -lntile' 'Libs.private: $(LIBS)' \
	  > '$(DESTDIR)$(PKGCONFIGDIR)/ntile.pc'
	printf '%s\n' 'prefix=$(PREFIX)' 'libdir=$(PC_LIBDIR)' 'includedir=$(PC_INCLUDEDIR)' '' \
	  'Name: ntile-game' \
	  'Description: ntile game layer: player controller, level objects, spawners, replay runner' \
	  'Version: $(VERSION)' 'Requires: ntile = $(VERSION)' 'Cflags: -I$${includedir}' 'Libs: -L$${libdir} -lntile-game $(LIBS)' \
	  > '$(DESTDIR)$(PKGCONFIGDIR)/ntile-game.pc'
	chmod 644 '$(DESTDIR)$(PKGCONFIGDIR)/ntile.pc' '$(DESTDIR)$(PKGCONFIGDIR)/ntile-game.pc'

# Removes the files install writes, and the include/ntile and share/ntile directories
# when they are empty; other directories stay (they may hold other packages' files).
uninstall:
	rm -f $(foreach h,$(notdir $(HEADERS)),'$(DESTDIR)$(INCLUDEDIR)/ntile/$(h)')
	-rmdir '$(DESTDIR)$(INCLUDEDIR)/ntile' 2>/dev/null || true
	rm -f $(foreach f,libntile.a libntile-game.a libntile.so libntile.so.$(SOVERSION) libntile.so.$(SOFULL),'$(DESTDIR)$(LIBDIR)/$(f)')
	rm -f '$(DESTDIR)$(PKGCONFIGDIR)/ntile.pc' '$(DESTDIR)$(PKGCONFIGDIR)/ntile-game.pc'
	rm -f '$(DESTDIR)$(BINDIR)/ntile' '$(DESTDIR)$(BINDIR)/ntile-play'
	rm -f $(foreach l,$(notdir $(LEVELS)),'$(DESTDIR)$(LEVELSDIR)/$(l)')
	-rmdir '$(DESTDIR)$(LEVELSDIR)' '$(DESTDIR)$(PREFIX)/share/ntile' 2>/dev/null || true

check-install: all deps-pkgconfig
	@MAKE='$(MAKE)' CC='$(CC)' VERSION='$(VERSION)' tools/check-install.sh

check-headers: $(BUILD)/libntile.a $(GAME_LIB) deps-cxx
	@CC='$(CC)' CXX='$(CXX)' CWARN='$(filter-out -Werror,$(WARN))' LIB='$(BUILD)/libntile.a' GAMELIB='$(GAME_LIB)' tools/check-headers.sh

# The picture in the README: the float build's sheet.
sheet: $(BUILD)/ntile
	$(BUILD)/ntile sheet -o tools/ntile/sheet.svg

clean:
	rm -rf build

-include $(shell find $(BUILD)/obj -name '*.d' 2>/dev/null)
