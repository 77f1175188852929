# Makefile - builds libjetmesh (static + shared), the jetmesh CLI, tests, demo, bench and fuzzers.
#
#   make            library, CLI               make check   every test (installs build + test deps)
#   make demo       convert the jet sample     make bench   benchmark suite -> BENCHMARKS.md
#                   (installs build deps only)
#   make fuzz       run the fuzzers            make install PREFIX=/usr/local
#   make kill-soak  signals at random moments, cores loaded (the long kill test)
#   make pictures   the README's renders (docs/*.png, headless Blender)

CC      ?= cc
CXX     ?= c++
OPT     ?= -O2 -g
CSTD     = -std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE
WARN     = -Wall -Wextra
CFLAGS  ?=
CXXFLAGS ?=
SAN     ?=
BUILD   ?= build
PREFIX  ?= /usr/local
DESTDIR ?=

# lib's own headers are named from lib/ ("core/internal.h"); the tests' white-box includes too
ALL_CFLAGS   = $(CSTD) $(OPT) $(WARN) $(SAN) -Ilib -fPIC -pthread -MMD -MP $(CFLAGS)
ALL_CXXFLAGS = -std=c++17 $(OPT) $(WARN) $(SAN) -fPIC -pthread -MMD -MP $(CXXFLAGS)
FMT_LIBS     = -ltinygltf -ldraco -lz
# the library's only dependency beyond libc: meshoptimizer (lib/post/simplify.c)
LIB_LIBS     = -lmeshoptimizer
LIBS         = $(FMT_LIBS) $(LIB_LIBS) -lstdc++ -lm -pthread

# lib/: the pipeline (mesh.c) and its stage folders (core, grid, field/*, extract, post)
LIB_SRC   := $(wildcard lib/*.c lib/*/*.c lib/*/*/*.c)
FMT_CSRC  := $(wildcard formats/*.c formats/*/*.c)
FMT_XSRC  := $(wildcard formats/*.cpp formats/*/*.cpp)
CLI_SRC   := $(wildcard cli/*.c cli/*/*.c)
TUTIL_SRC := $(wildcard tests/util/*.c)
TEST_SRC  := $(wildcard tests/test_*.c)
TOOL_SRC  := $(wildcard tests/tools/*.c)

LIB_OBJ   := $(LIB_SRC:%.c=$(BUILD)/%.o)
FMT_OBJ   := $(FMT_CSRC:%.c=$(BUILD)/%.o) $(FMT_XSRC:%.cpp=$(BUILD)/%.o)
CLI_OBJ   := $(CLI_SRC:%.c=$(BUILD)/%.o)
TUTIL_OBJ := $(TUTIL_SRC:%.c=$(BUILD)/%.o)
# the tests' mesh figures (tests/util/meshmetrics.c) measure distances as the bench's flicker figure
# does, and their inputs are jetmesh generate's scenes
TUTIL_OBJ += $(BUILD)/cli/bench/mesh_distance.o $(BUILD)/cli/scenes.o $(BUILD)/cli/scenes_liquid.o
TEST_BIN  := $(TEST_SRC:tests/%.c=$(BUILD)/bin/%)
TOOL_BIN  := $(TOOL_SRC:tests/tools/%.c=$(BUILD)/tools/%)

LIBA  = $(BUILD)/libjetmesh.a
LIBSO = $(BUILD)/libjetmesh.so
FMTA  = $(BUILD)/libjetmesh_formats.a
CLI   = $(BUILD)/jetmesh

.SECONDARY:

.PHONY: all deps deps-build print-libs print-tutil check kill-soak pictures test-unit test-scripts demo bench bench-large fuzz fuzz-build install clean asan

all: $(LIBA) $(LIBSO) $(CLI)

# the library's hot loops want the vectoriser
LIB_OPT ?= -O3 -g -fno-math-errno -fno-trapping-math
$(LIB_OBJ): OPT = $(LIB_OPT)
# lanes8.h's vectors live in static functions only, inlined into each
# CPU's clone: the note that passing them would change the ABI is moot
$(BUILD)/lib/field/meta/metaroot.o $(BUILD)/lib/field/meta/metavertex.o $(BUILD)/lib/post/cavities.o \
  $(BUILD)/lib/post/smooth_implicit.o: WARN += -Wno-psabi

$(BUILD)/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -c $< -o $@

$(BUILD)/%.o: %.cpp
	@mkdir -p $(dir $@)
	$(CXX) $(ALL_CXXFLAGS) -c $< -o $@

$(LIBA): $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(LIBSO): $(LIB_OBJ)
	$(CC) -shared $(SAN) -pthread -o $@ $^ $(LIB_LIBS) -lm

$(FMTA): $(FMT_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(CLI): $(CLI_OBJ) $(FMTA) $(LIBA)
	$(CC) $(SAN) -o $@ $(CLI_OBJ) $(FMTA) $(LIBA) $(LIBS)

$(BUILD)/bin/%: $(BUILD)/tests/%.o $(TUTIL_OBJ) $(FMTA) $(LIBA)
	@mkdir -p $(dir $@)
	$(CC) $(SAN) -o $@ $< $(TEST_OBJ) $(TUTIL_OBJ) $(FMTA) $(LIBA) -lcmocka $(LIBS)

# the CLI's text readers, tested alone
TEXT_OBJ := $(patsubst %.c,$(BUILD)/%.o,$(wildcard cli/text/*.c))
$(BUILD)/bin/test_text_read: TEST_OBJ = $(TEXT_OBJ)
$(BUILD)/bin/test_text_read: $(TEXT_OBJ)

$(BUILD)/tools/%: $(BUILD)/tests/tools/%.o $(TUTIL_OBJ) $(FMTA) $(LIBA)
	@mkdir -p $(dir $@)
	$(CC) $(SAN) -o $@ $< $(TUTIL_OBJ) $(FMTA) $(LIBA) $(LIBS)

deps:
	@scripts/deps.sh all

deps-build:
	@scripts/deps.sh build

# The test command: installs what is missing (build packages and the test
# tools: Blender, Slurm, munge, node...), builds, runs every test.
check: deps
	@$(MAKE) --no-print-directory all tests-build
	@tests/run_all.sh $(BUILD)

tests-build: $(TEST_BIN) $(TOOL_BIN) $(CLI)

# the CLI's link libraries, for a test that links the CLI's objects with a
# library built otherwise (t_splat_variants.sh)
print-libs:
	@echo $(LIBS)

# the tests' shared objects, for a test that links a test binary by hand
# (t_aniso_cull_broken.sh)
print-tutil:
	@echo $(TUTIL_OBJ)

test-unit: tests-build
	@tests/run_all.sh $(BUILD) unit

test-scripts: tests-build
	@tests/run_all.sh $(BUILD) scripts

# The kill race, hard: 216 signals at random moments with both cores loaded.
kill-soak: tests-build
	@KILL_ROUNDS=$${KILL_ROUNDS:-24} JETMESH_ROOT=$(CURDIR) JETMESH=$(CURDIR)/$(BUILD)/jetmesh \
	    JETMESH_BUILD=$(CURDIR)/$(BUILD) sh tests/t_cli_kill_race.sh

# The README's pictures (docs/*.png), rendered by headless Blender.
pictures: all $(BUILD)/tools/to_xyz
	@scripts/pictures.sh $(BUILD)

# The main job: convert the shipped jet sequence (see README). Installs the
# build packages only (the test tools: make check).
demo: deps-build
	@$(MAKE) --no-print-directory all
	@scripts/demo.sh $(BUILD)

bench: deps-build
	@$(MAKE) --no-print-directory all
	@scripts/bench.sh $(BUILD)

# Opt-in, minutes and about 2 GB: the 8M block against the 1M block and a
# 13.35M block -> BENCHMARKS_LARGE.md.
bench-large: deps-build
	@$(MAKE) --no-print-directory all
	@scripts/bench_large.sh $(BUILD)

fuzz: deps
	@scripts/fuzz.sh

install: all
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/lib $(DESTDIR)$(PREFIX)/include \
	           $(DESTDIR)$(PREFIX)/share/man/man1
	install -m 755 $(CLI) $(DESTDIR)$(PREFIX)/bin/jetmesh
	install -m 644 $(LIBA) $(LIBSO) $(DESTDIR)$(PREFIX)/lib/
	install -m 644 lib/jetmesh.h $(DESTDIR)$(PREFIX)/include/
	install -m 644 man/jetmesh.1 $(DESTDIR)$(PREFIX)/share/man/man1/
	@# the Blender importer of sequences (jetmesh --blender-script) and pkg-config
	install -d $(DESTDIR)$(PREFIX)/share/jetmesh $(DESTDIR)$(PREFIX)/lib/pkgconfig
	install -m 644 share/jetmesh/jetmesh_blender.py $(DESTDIR)$(PREFIX)/share/jetmesh/
	sed -e 's|@PREFIX@|$(PREFIX)|' \
	    -e "s|@VERSION@|$$(sed -n 's/^#define JM_VERSION_STRING \"\(.*\)\"/\1/p' lib/jetmesh.h)|" \
	    share/jetmesh.pc.in > $(DESTDIR)$(PREFIX)/lib/pkgconfig/jetmesh.pc

clean:
	rm -rf $(BUILD) build-asan build-tsan build-noclones

-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)
