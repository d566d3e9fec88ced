# ntile — one Makefile for the library, the tools and the tests.
#
#   make                 library (static + shared) and the ntile CLI, in build/
#   make test            build and run every test
#   make asan            the whole test suite under AddressSanitizer + UBSan
#   make run             the quick-start demonstration
#   make NT_DOUBLE=1 …   everything with double as the scalar type
#   make CC=clang OPT=-O3 …  any compiler / optimisation level
#   make bench           the world scenes: ns per body-step and error metrics, scaling
#   make bench-sweep     run time against error: dt, substeps, iterations, friction model,
#                        float and double (CSV + SVG in build/sweep/)
#   make bench-peers     the same scenes in Chipmunk2D 7 and Box2D 2.4 (Debian's
#                        libchipmunk-dev and libbox2d-dev, installed when missing)
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
CFLAGS_ALL := -std=c11 $(OPT) $(SAN) $(WARN) -ffp-contract=off -fPIC -fno-semantic-interposition \
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

SOVERSION := 0
SOFULL := 0.1.0

LIB_SRC := $(wildcard src/*.c)
LIB_OBJ := $(LIB_SRC:%.c=$(OBJ)/%.o)
CLI_SRC := $(wildcard tools/ntile/*.c)
CLI_OBJ := $(CLI_SRC:%.c=$(OBJ)/%.o)
TEST_SRC := $(wildcard tests/test_*.c)
TEST_BIN := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)
TEST_LIB_SRC := $(filter-out $(TEST_SRC),$(wildcard tests/*.c))
TEST_LIB_OBJ := $(TEST_LIB_SRC:%.c=$(OBJ)/%.o)

.PHONY: all lib cli test asan determinism run clean deps-cc deps-test bench bench-sweep bench-peers deps-peers
.DEFAULT_GOAL := all
# Keep objects of tests (make would delete them as intermediates).
.SECONDARY:

all: lib cli
lib: $(BUILD)/libntile.a $(BUILD)/libntile.so
cli: $(BUILD)/ntile

deps-cc:
	@tools/deps.sh cc
deps-test:
	@tools/deps.sh cc cmocka

$(OBJ)/%.o: %.c | deps-cc
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

$(BUILD)/ntile: $(CLI_OBJ) $(BUILD)/libntile.a
	$(CC) $(LDFLAGS_ALL) -o $@ $(CLI_OBJ) $(BUILD)/libntile.a $(LIBS)

# Tests: one cmocka binary per tests/test_*.c, linked with the shared test helpers
# (test_bench also with the benchmark's metric, scene, outline and plot code).
TEST_EXTRA_OBJ = $(if $(filter test_bench,$*),$(addprefix $(OBJ)/tools/ntile/,scene.o metrics.o plot.o bench_common.o geometry.o))
.SECONDEXPANSION:
$(BUILD)/tests/%: $(OBJ)/tests/%.o $(TEST_LIB_OBJ) $$(TEST_EXTRA_OBJ) $(BUILD)/libntile.a | deps-test
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS_ALL) -o $@ $< $(TEST_LIB_OBJ) $(TEST_EXTRA_OBJ) $(BUILD)/libntile.a -lcmocka $(LIBS)

$(OBJ)/tests/%.o: tests/%.c | deps-test
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) -Isrc -Itools/ntile -MMD -MP -c $< -o $@

test: deps-test $(TEST_BIN) $(BUILD)/ntile
	@pass=0; fail=0; for t in $(TEST_BIN); do \
	  echo "== $$t"; if NTILE=$(BUILD)/ntile $$t; then pass=$$((pass+1)); else fail=$$((fail+1)); echo "FAILED: $$t"; fi; \
	done; \
	echo "test suites: $$pass passed, $$fail failed"; [ $$fail -eq 0 ]

BUILD_ASAN ?= build/asan
asan:
	@$(MAKE) --no-print-directory BUILD=$(BUILD_ASAN) OPT="-O1 -g" \
	  SAN="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer" test

# The golden world hash must come out of gcc and clang at -O0, -O2 and -O3, in both
# scalar builds: test_world pins it (test_determinism_and_golden_hash).
DET_CCS ?= gcc clang
DET_OPTS ?= -O0 -O2 -O3
determinism:
	@set -e; for cc in $(DET_CCS); do for o in $(DET_OPTS); do for d in 0 1; do \
	  b=build/det/$$cc$$o-$$d; \
	  $(MAKE) --no-print-directory -s BUILD=$$b CC=$$cc OPT=$$o NT_DOUBLE=$$d $$b/tests/test_world >/dev/null; \
	  printf '%-6s %-4s %-6s ' $$cc $$o $$( [ $$d = 1 ] && echo double || echo float ); \
	  $$b/tests/test_world 2>&1 | grep -q '^\[  PASSED  \]' || { echo FAILED; $$b/tests/test_world; exit 1; }; \
	  $$b/tests/test_world 2>&1 | grep 'golden hash'; \
	done; done; done

# ---- benchmarks: figures measured on the machine that runs them (RUNS >= 5) ----
RUNS ?= 5
BENCH_SCENES ?= rain particles sparse pile asleep slide bounce gas incline flight rest tunnel
bench: $(BUILD)/ntile
	$(BUILD)/ntile bench world $(BENCH_SCENES) --runs $(RUNS)
	$(BUILD)/ntile bench scaling --runs $(RUNS)

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
PEER_SRC := $(wildcard tools/bench-peers/*.c)
PEER_OBJ := $(PEER_SRC:%.c=$(OBJ)/%.o) $(OBJ)/tools/bench-peers/box2d_shim.o
BENCH_SHARED_OBJ := $(addprefix $(OBJ)/tools/ntile/,scene.o metrics.o engine_ntile.o bench_run.o bench_common.o geometry.o)
deps-peers:
	@tools/deps.sh cc cxx chipmunk box2d

$(OBJ)/tools/bench-peers/%.o: tools/bench-peers/%.c | deps-peers
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) -Itools/ntile -MMD -MP -c $< -o $@

$(OBJ)/tools/bench-peers/box2d_shim.o: tools/bench-peers/box2d_shim.cpp | deps-peers
	@mkdir -p $(dir $@)
	$(CXX) -std=c++11 $(OPT) $(filter-out -Wmissing-prototypes,$(WARN)) -ffp-contract=off -MMD -MP -c $< -o $@

$(BUILD)/bench-peers: $(PEER_OBJ) $(BENCH_SHARED_OBJ) $(BUILD)/libntile.a
	$(CXX) $(LDFLAGS_ALL) -o $@ $(PEER_OBJ) $(BENCH_SHARED_OBJ) $(BUILD)/libntile.a -lchipmunk -lbox2d $(LIBS)

bench-peers: deps-peers $(BUILD)/bench-peers
	$(BUILD)/bench-peers --runs $(RUNS)

run: $(BUILD)/ntile
	$(BUILD)/ntile query levels/demo.query

clean:
	rm -rf build

-include $(shell find $(BUILD)/obj -name '*.d' 2>/dev/null)
