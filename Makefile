# terrain LOD toolchain: dem2fqm fqmfilter fqmsolve tilepack tileplay
# tilecheck dem2vgis vgis2tiles
# make            build everything (installs missing Debian packages first)
# make check      build and run every test
# make example    build a pyramid from the default example DEM
# make bench      measure errors, speed and memory on ../shared/data
#                 (scripts/bench: the filters; scripts/bench-pyramid: DEM to
#                 pyramid, triangle counts and real errors; scripts/bench-tiles:
#                 the 3D Tiles export)
# make install    PREFIX=/usr/local DESTDIR=

PREFIX  ?= /usr/local
BINDIR  ?= $(PREFIX)/bin
LIBDIR  ?= $(PREFIX)/lib/terrain-lod
MANDIR  ?= $(PREFIX)/share/man
B       := build

CC      ?= cc
CXX     ?= c++
CFLAGS  ?= -O2 -g
CXXFLAGS ?= -O2 -g
WARN    := -Wall -Wextra -Wshadow -Wstrict-prototypes -Wno-unused-parameter

# The library is five layers, each an archive, dependencies one way:
# core (rasters, DEM input, georeferencing, quadrics) <- pyramid (bintree,
# blocks, checker) <- play (camera, meshes, cache, GL); pyramid <- tiles3d
# (the 3D Tiles export: glTF, tileset.json); core <- jobs (the
# supervisor of process graphs, scratch, the DEM-to-pyramid pipeline). A
# program links the layers it uses and their packages only
# (tests/cmd/t_layers.sh checks includes, archives and links). Package flags are resolved when a recipe runs, i.e. after
# $(B)/.deps has installed them.
CORE_PKGS := OpenEXR gdal geographiclib proj libdeflate
PYR_PKGS  := jansson
PLAY_PKGS := egl epoxy glfw3 stb
TEST_PKGS := libtiff-4 jansson zlib
PKGS    := $(CORE_PKGS) $(PYR_PKGS) $(PLAY_PKGS) $(TEST_PKGS) OpenImageIO
pkgcf    = $(shell pkg-config --cflags $(1))
pkglibs  = $(shell pkg-config --libs $(1))
ALLCFLAGS = -std=c11 -D_DEFAULT_SOURCE $(WARN) $(CFLAGS) \
            $(call pkgcf,$(CORE_PKGS) $(PYR_PKGS) $(PLAY_PKGS) $(TEST_PKGS)) \
            -Isrc/lib -DTL_LIBDIR='"$(LIBDIR)"'
ALLCXXFLAGS = -std=c++17 -Wall -Wextra $(CXXFLAGS) -Isrc/lib \
            $(call pkgcf,geographiclib gdal)
SYSLIBS  = -lstdc++ -lm -lpthread -ldl

LAYERS  := core pyramid play jobs tiles3d
objs     = $(patsubst src/lib/%.c,$(B)/lib/%.o,$(wildcard src/lib/$(1)/*.c)) \
           $(patsubst src/lib/%.cpp,$(B)/lib/%.o,$(filter-out %/oiio_plugin.cpp,$(wildcard src/lib/$(1)/*.cpp)))
CORE_A  := $(B)/libcore.a
PYR_A   := $(B)/libpyramid.a
PLAY_A  := $(B)/libplay.a
JOBS_A  := $(B)/libjobs.a
T3_A    := $(B)/libtiles3d.a
CORE_LD  = $(CORE_A) -Wl,--as-needed $(call pkglibs,$(CORE_PKGS)) -lOpenEXRCore-3_1 $(SYSLIBS)
PYR_LD   = $(PYR_A) $(CORE_A) -Wl,--as-needed $(call pkglibs,$(PYR_PKGS) $(CORE_PKGS)) -lOpenEXRCore-3_1 $(SYSLIBS)
PLAY_LD  = $(PLAY_A) $(PYR_A) $(CORE_A) -Wl,--as-needed \
           $(call pkglibs,$(PLAY_PKGS) $(PYR_PKGS) $(CORE_PKGS)) -lOpenEXRCore-3_1 $(SYSLIBS)
JOBS_LD  = $(JOBS_A) $(CORE_LD)
T3_LD    = $(T3_A) $(PYR_LD)

PROGS   := dem2fqm fqmfilter fqmsolve tilepack tileplay tilecheck dem2vgis vgis2tiles
# OpenImageIO costs 130 MB of RSS just by being linked (260 shared libraries):
# it lives in a plugin loaded only for EXR input and PNG output.
PLUGIN  := $(B)/tl_oiio.so
# tests/<layer>/t_<module>.c, one per module, linked with their layer;
# tests/cmd/t_*.sh run the programs
TESTC   := $(wildcard tests/*/t_*.c)
TESTBIN := $(TESTC:tests/%.c=$(B)/tests/%)
TOOLC   := $(wildcard tests/tools/*.c)
TOOLBIN := $(TOOLC:tests/tools/%.c=$(B)/tools/%)
MAN1    := $(PROGS:%=man/%.1)
MAN5    := $(wildcard man/*.5)

all: $(PROGS:%=$(B)/%) $(PLUGIN)

# Install the Debian packages the build needs, once, when one is missing.
$(B)/.deps:
	@mkdir -p $(B)
	@if ! command -v pkg-config >/dev/null || \
	    ! pkg-config --exists $(PKGS) libpng || \
	    ! test -f /usr/share/proj/egm96_15.gtx; then \
		echo "make: missing build dependencies; running scripts/install-deps"; \
		sh scripts/install-deps; \
	fi
	@touch $@

# Objects depend on the headers they include (-MMD -MP, build/**/*.d).
$(B)/lib/%.o: src/lib/%.c | $(B)/.deps
	@mkdir -p $(@D)
	$(CC) $(ALLCFLAGS) -MMD -MP -c $< -o $@

$(B)/lib/%.o: src/lib/%.cpp | $(B)/.deps
	@mkdir -p $(@D)
	$(CXX) $(ALLCXXFLAGS) -MMD -MP -c $< -o $@

$(PLUGIN): src/lib/core/oiio_plugin.cpp src/lib/core/oiio_plugin.h | $(B)/.deps
	$(CXX) -shared -fPIC $(ALLCXXFLAGS) $(call pkgcf,OpenImageIO) -o $@ $< \
	    $(call pkglibs,OpenImageIO)

$(CORE_A): $(call objs,core)
$(PYR_A): $(call objs,pyramid)
$(PLAY_A): $(call objs,play)
$(JOBS_A): $(call objs,jobs)
$(T3_A): $(call objs,tiles3d)
$(CORE_A) $(PYR_A) $(PLAY_A) $(JOBS_A) $(T3_A):
	rm -f $@
	ar rcs $@ $^

$(B)/cmd/%.o: src/cmd/%.c | $(B)/.deps
	@mkdir -p $(@D)
	$(CC) $(ALLCFLAGS) -MMD -MP -c $< -o $@

# Each program with the layers it uses.
$(B)/dem2fqm $(B)/fqmfilter $(B)/fqmsolve: $(B)/%: $(B)/cmd/%.o $(CORE_A)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $< $(CORE_LD)
$(B)/tilepack $(B)/tilecheck: $(B)/%: $(B)/cmd/%.o $(PYR_A) $(CORE_A)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $< $(PYR_LD)
$(B)/tileplay: $(B)/%: $(B)/cmd/%.o $(PLAY_A) $(PYR_A) $(CORE_A)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $< $(PLAY_LD)
$(B)/dem2vgis: $(B)/%: $(B)/cmd/%.o $(JOBS_A) $(CORE_A)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $< $(JOBS_LD)
$(B)/vgis2tiles: $(B)/%: $(B)/cmd/%.o $(T3_A) $(PYR_A) $(CORE_A)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $< $(T3_LD)

TESTFLAGS = $(ALLCFLAGS) -Itests -MMD -MP
TEST_LD  = $(call pkglibs,$(TEST_PKGS))
$(B)/tests/core/%: tests/core/%.c tests/tap.h $(CORE_A)
	@mkdir -p $(@D)
	$(CC) $(TESTFLAGS) $(LDFLAGS) -o $@ $< $(CORE_LD) $(TEST_LD)
$(B)/tests/pyramid/%: tests/pyramid/%.c tests/tap.h $(PYR_A) $(CORE_A)
	@mkdir -p $(@D)
	$(CC) $(TESTFLAGS) $(LDFLAGS) -o $@ $< $(PYR_LD) $(TEST_LD)
$(B)/tests/play/%: tests/play/%.c tests/tap.h $(PLAY_A) $(PYR_A) $(CORE_A)
	@mkdir -p $(@D)
	$(CC) $(TESTFLAGS) $(LDFLAGS) -o $@ $< $(PLAY_LD) $(TEST_LD)
$(B)/tests/jobs/%: tests/jobs/%.c tests/tap.h $(JOBS_A) $(CORE_A)
	@mkdir -p $(@D)
	$(CC) $(TESTFLAGS) $(LDFLAGS) -o $@ $< $(JOBS_LD) $(TEST_LD)
$(B)/tests/tiles3d/%: tests/tiles3d/%.c tests/tap.h $(T3_A) $(PYR_A) $(CORE_A)
	@mkdir -p $(@D)
	$(CC) $(TESTFLAGS) $(LDFLAGS) -o $@ $< $(T3_LD) $(TEST_LD)

$(B)/tools/%: tests/tools/%.c $(PLAY_A) $(PYR_A) $(CORE_A)
	@mkdir -p $(@D)
	$(CC) $(ALLCFLAGS) $(LDFLAGS) -o $@ $< $(PLAY_LD) $(TEST_LD)

# Fuzz targets (tests/fuzz/fz_*.c): in make check each is replayed over its
# seeds and regression inputs by an ordinary build (replay.c); make fuzz
# runs each under libFuzzer for FUZZ_TIME seconds on a clang
# ASan+UBSan build of its own (build-fuzz/).
FUZZC   := $(wildcard tests/fuzz/fz_*.c)
FUZZ    := $(FUZZC:tests/fuzz/fz_%.c=%)
FUZZREPLAY := $(FUZZ:%=$(B)/tests/fuzz/fz_%)
$(B)/tests/fuzz/fz_%: tests/fuzz/fz_%.c tests/fuzz/fuzz.c tests/fuzz/replay.c \
    tests/fuzz/fuzz.h $(PYR_A) $(CORE_A)
	@mkdir -p $(@D)
	$(CC) $(TESTFLAGS) -Itests/fuzz $(LDFLAGS) -o $@ $< tests/fuzz/fuzz.c \
	    tests/fuzz/replay.c $(PYR_LD)

# The validators of tests/js (npm, locked), installed once.
NODE_DEPS := tests/js/node_modules/.package-lock.json
# The tests' npm packages (validators, CesiumJS, playwright-core), locked;
# npm itself comes with the test packages of scripts/install-deps.
$(NODE_DEPS): tests/js/package.json tests/js/package-lock.json
	@command -v npm >/dev/null || { echo "make: npm missing; running scripts/install-deps"; sh scripts/install-deps; }
	cd tests/js && npm ci --no-audit --no-fund --loglevel=error

tests: all $(TESTBIN) $(TOOLBIN) $(FUZZREPLAY) $(NODE_DEPS)

check: tests
	@sh tests/run

example: all $(TOOLBIN)
	sh examples/run

bench: all $(TOOLBIN)
	sh scripts/bench
	sh scripts/bench-pyramid
	sh scripts/bench-play
	sh scripts/bench-tiles

install: all
	install -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR) $(DESTDIR)$(MANDIR)/man1 $(DESTDIR)$(MANDIR)/man5
	install -m 644 $(PLUGIN) $(DESTDIR)$(LIBDIR)
	install -m 755 $(PROGS:%=$(B)/%) $(DESTDIR)$(BINDIR)
	install -m 644 $(MAN1) $(DESTDIR)$(MANDIR)/man1
	install -m 644 $(MAN5) $(DESTDIR)$(MANDIR)/man5

clean:
	rm -rf $(B)/lib $(B)/cmd $(B)/tests $(B)/tools $(B)/*.a $(PLUGIN) $(PROGS:%=$(B)/%)

# tilepack and dem2vgis on a real DEM under ThreadSanitizer (a build of
# their own in build-tsan/, the levels on parallel threads).
check-tsan:
	$(MAKE) B=build-tsan CFLAGS='-O1 -g -fsanitize=thread' \
	    CXXFLAGS='-O1 -g -fsanitize=thread' LDFLAGS=-fsanitize=thread all
	sh tests/tsan build-tsan

FUZZ_TIME ?= 60
FZ_FLAGS = -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined \
           -fno-sanitize-recover=undefined
# clang's vptr check needs its C++ runtime, which the C driver that links
# the programs leaves out; the dynamic types checked would be GDAL's.
FZ_CXXFLAGS = $(FZ_FLAGS) -fno-sanitize=vptr
fuzz:
	$(MAKE) B=build-fuzz CC=clang CXX=clang++ \
	    CFLAGS='$(FZ_FLAGS) -fsanitize=fuzzer-no-link' \
	    CXXFLAGS='$(FZ_CXXFLAGS) -fsanitize=fuzzer-no-link' \
	    LDFLAGS='-fsanitize=address,undefined' fuzz-targets
	sh tests/fuzz/run build-fuzz $(FUZZ_TIME) $(FUZZ)

fuzz-targets: all $(FUZZ:%=$(B)/fuzz/fz_%)
$(B)/fuzz/fz_%: tests/fuzz/fz_%.c tests/fuzz/fuzz.c tests/fuzz/fuzz.h \
    $(PYR_A) $(CORE_A)
	@mkdir -p $(@D)
	$(CC) $(TESTFLAGS) -Itests/fuzz -fsanitize=fuzzer -o $@ $< \
	    tests/fuzz/fuzz.c $(PYR_LD)

# The whole suite on an AddressSanitizer + UndefinedBehaviorSanitizer build
# of its own (build-asan/): any report fails the test that caused it. It
# runs several times slower: TL_QUICK leaves the largest DEM out of the
# heaviest tests (tests/lib.sh).
ASAN_FLAGS = -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined \
             -fno-sanitize-recover=undefined
check-asan:
	$(MAKE) B=build-asan CFLAGS='$(ASAN_FLAGS)' CXXFLAGS='$(ASAN_FLAGS)' \
	    LDFLAGS='-fsanitize=address,undefined' tests
	ASAN_OPTIONS=abort_on_error=0:exitcode=66:suppressions=$(CURDIR)/tests/asan.supp \
	LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp \
	UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:exitcode=66 \
	TL_QUICK=1 TL_BUILD=build-asan sh tests/run

-include $(shell find $(B) -name '*.d' 2>/dev/null)

.PHONY: all tests check check-tsan check-asan fuzz fuzz-targets example bench install clean
.SECONDARY:
