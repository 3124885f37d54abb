# terrain LOD toolchain: dem2fqm fqmfilter fqmsolve tilepack tileplay
# tilecheck dem2vgis vgis2tiles vgis2terrain (and vgis-job, the steps plans run)
# make            build everything (installs missing Debian packages first)
# make check      build and run every test
# make example    build a pyramid from the default example DEM
# make bench      measure errors, speed and memory on ../shared/data
#                 (scripts/bench: the filters; scripts/bench-pyramid: DEM to
#                 pyramid, triangle counts and real errors; scripts/bench-tiles:
#                 the 3D Tiles export; scripts/bench-terrain: the terrain)
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

# The library's layers, bottom up: the one table. Each is a folder of
# src/lib, an archive build/libNAME.a, a folder of tests/, and the only
# owner of its foreign packages. uses_L: the layers L's files may include
# (directly; what those use comes with them); pkgs_L: its packages.
# Link lines, test rules and tests/cmd/t_layers.sh (make print-layers)
# all derive from it.
LAYERS := base geo raster dem qem pyramid pack verify play tiles3d terrain rgb jobs
uses_base    :=
uses_geo     := base
uses_raster  := base geo
uses_dem     := base geo raster
uses_qem     := base geo raster dem
uses_pyramid := base geo raster
uses_pack    := base geo raster dem qem pyramid
uses_verify  := base geo raster dem pyramid
uses_play    := base geo raster pyramid
uses_tiles3d := base geo pyramid
uses_terrain := base geo pyramid
uses_rgb     := base geo raster dem qem pyramid
uses_jobs    := base raster qem
pkgs_base    := jansson zlib
pkgs_geo     := proj geographiclib
pkgs_raster  := OpenEXR libdeflate
libs_raster  := -lOpenEXRCore-3_1
pkgs_dem     := gdal
pkgs_play    := egl epoxy glfw3 stb
pkgs_terrain := glu
pkgs_rgb     := libpng libwebp
# the programs: the layers each uses (cli.c, their shared start-up, uses
# uses_cli; the other files of src/cmd, the work the programs share, are
# build/libcmd.a, of which each links what it calls)
uses_cli        := base raster dem
uses_dem2fqm    := qem
uses_fqmfilter  := qem
uses_fqmsolve   := qem
uses_tilepack   := pack
uses_tilecheck  := verify
uses_tileplay   := play verify
uses_dem2vgis   := jobs pack
uses_vgis2tiles := tiles3d
uses_vgis2terrain := terrain jobs
uses_dem2rgb    := rgb jobs
uses_vgis-job   := jobs pack terrain rgb
# what a layer's tests use beside it: the packer's results are checked by
# the independent checker
tests_pack      := verify
TEST_PKGS := libtiff-4 jansson zlib
LAYER_PKGS = $(sort $(foreach l,$(LAYERS),$(pkgs_$(l))))
PKGS    := $(LAYER_PKGS) $(TEST_PKGS) OpenImageIO
pkgcf    = $(shell pkg-config --cflags $(1))
pkglibs  = $(shell pkg-config --libs $(1))
ALLCFLAGS = -std=c11 -D_DEFAULT_SOURCE $(WARN) $(CFLAGS) \
            $(call pkgcf,$(LAYER_PKGS) $(TEST_PKGS)) \
            -Isrc/lib -DTL_LIBDIR='"$(LIBDIR)"'
ALLCXXFLAGS = -std=c++17 -Wall -Wextra $(CXXFLAGS) -Isrc/lib \
            $(call pkgcf,geographiclib gdal)
SYSLIBS  = -lstdc++ -lm -lpthread -ldl

# closure LAYERS: them and every layer below them they use
closure  = $(sort $(foreach l,$(1),$(l) $(call closure,$(uses_$(l)))))
reverse  = $(if $(1),$(call reverse,$(wordlist 2,$(words $(1)),$(1))) $(firstword $(1)))
# archives LAYERS: their archives and those below, top down (link order)
archives = $(foreach l,$(call reverse,$(LAYERS)),$(if $(filter $(l),$(call closure,$(1))),$(B)/lib$(l).a))
# ld LAYERS: the link line of a program or test using LAYERS
ld       = $(call archives,$(1)) -Wl,--as-needed \
           $(call pkglibs,$(sort $(foreach l,$(call closure,$(1)),$(pkgs_$(l))))) \
           $(foreach l,$(call closure,$(1)),$(libs_$(l))) $(SYSLIBS)
objs     = $(patsubst src/lib/%.c,$(B)/lib/%.o,$(wildcard src/lib/$(1)/*.c)) \
           $(patsubst src/lib/%.cpp,$(B)/lib/%.o,$(filter-out %/oiio_plugin.cpp,$(wildcard src/lib/$(1)/*.cpp)))

PROGS   := dem2fqm fqmfilter fqmsolve tilepack tileplay tilecheck dem2vgis vgis2tiles vgis2terrain vgis-job dem2rgb
CMDOBJS := $(patsubst src/cmd/%.c,$(B)/cmd/%.o,$(filter-out $(PROGS:%=src/cmd/%.c),$(wildcard src/cmd/*.c)))
# OpenImageIO costs 130 MB of RSS just by being linked (260 shared libraries):
# it lives in a plugin loaded only for EXR input and PNG output.
PLUGIN  := $(B)/tl_oiio.so
# tests/<layer>/t_<module>.c, one per module, linked with their layer;
# tests/cmd/t_*.c with cli.o; tests/cmd/t_*.sh run the programs
TESTC   := $(wildcard tests/*/t_*.c)
TESTBIN := $(TESTC:tests/%.c=$(B)/tests/%)
TOOLC   := $(wildcard tests/tools/*.c)
TOOLBIN := $(TOOLC:tests/tools/%.c=$(B)/tools/%)
MAN1    := $(PROGS:%=man/%.1)
MAN5    := $(wildcard man/*.5)
MAN7    := $(wildcard man/*.7)

all: $(PROGS:%=$(B)/%) $(PLUGIN)

print-layers:
	@$(foreach l,$(LAYERS),echo "$(l): $(call closure,$(l)): $(pkgs_$(l))";)

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

$(PLUGIN): src/lib/raster/oiio_plugin.cpp src/lib/raster/oiio_plugin.h | $(B)/.deps
	$(CXX) -shared -fPIC $(ALLCXXFLAGS) $(call pkgcf,OpenImageIO) -o $@ $< \
	    $(call pkglibs,OpenImageIO)

$(foreach l,$(LAYERS),$(eval $(B)/lib$(l).a: $(call objs,$(l))))
$(LAYERS:%=$(B)/lib%.a):
	rm -f $@
	ar rcs $@ $^

$(B)/cmd/%.o: src/cmd/%.c | $(B)/.deps
	@mkdir -p $(@D)
	$(CC) $(ALLCFLAGS) -MMD -MP -c $< -o $@

$(B)/libcmd.a: $(CMDOBJS)
	rm -f $@
	ar rcs $@ $^

# Each program with libcmd.a (cli.o...) and the layers it uses.
define prog_rule
$(B)/$(1): $(B)/cmd/$(1).o $(B)/libcmd.a $(call archives,$(uses_$(1)) $(uses_cli))
	$$(CC) $$(CFLAGS) $$(LDFLAGS) -o $$@ $(B)/cmd/$(1).o $(B)/libcmd.a \
	    $$(call ld,$(uses_$(1)) $(uses_cli))
endef
$(foreach p,$(PROGS),$(eval $(call prog_rule,$(p))))

TESTFLAGS = $(ALLCFLAGS) -Itests -MMD -MP
TEST_LD  = $(call pkglibs,$(TEST_PKGS))
# tests/LAYER/t_*.c with LAYER and what it uses
define test_rule
$(B)/tests/$(1)/%: tests/$(1)/%.c tests/tap.h $(call archives,$(1) $(tests_$(1)))
	@mkdir -p $$(@D)
	$$(CC) $$(TESTFLAGS) $$(LDFLAGS) -o $$@ $$< $$(call ld,$(1) $(tests_$(1))) $$(TEST_LD)
endef
$(foreach l,$(LAYERS),$(eval $(call test_rule,$(l))))
$(B)/tests/cmd/%: tests/cmd/%.c tests/tap.h $(B)/cmd/cli.o $(call archives,$(uses_cli))
	@mkdir -p $(@D)
	$(CC) $(TESTFLAGS) -Isrc/cmd $(LDFLAGS) -o $@ $< $(B)/cmd/cli.o \
	    $(call ld,$(uses_cli)) $(TEST_LD)

$(B)/tools/%: tests/tools/%.c $(call archives,$(LAYERS))
	@mkdir -p $(@D)
	$(CC) $(ALLCFLAGS) $(LDFLAGS) -o $@ $< $(call ld,$(LAYERS)) $(TEST_LD)

# Fuzz targets (tests/fuzz/fz_*.c): in make check each is replayed over its
# seeds and regression inputs by an ordinary build (replay.c); make fuzz
# runs each under libFuzzer for FUZZ_TIME seconds on a clang
# ASan+UBSan build of its own (build-fuzz/).
FUZZC   := $(wildcard tests/fuzz/fz_*.c)
FUZZ    := $(FUZZC:tests/fuzz/fz_%.c=%)
FUZZREPLAY := $(FUZZ:%=$(B)/tests/fuzz/fz_%)
FUZZ_USES := verify pack $(uses_cli)
$(B)/tests/fuzz/fz_%: tests/fuzz/fz_%.c tests/fuzz/fuzz.c tests/fuzz/replay.c \
    tests/fuzz/fuzz.h $(B)/cmd/cli.o $(call archives,$(FUZZ_USES))
	@mkdir -p $(@D)
	$(CC) $(TESTFLAGS) -Itests/fuzz -Isrc/cmd $(LDFLAGS) -o $@ $< tests/fuzz/fuzz.c \
	    tests/fuzz/replay.c $(B)/cmd/cli.o $(call ld,$(FUZZ_USES))

# The validators of tests/js (npm, locked), installed once.
NODE_DEPS := tests/js/node_modules/.package-lock.json
# The tests' npm packages (validators, CesiumJS, playwright-core), locked;
# npm itself comes with the test packages of scripts/install-deps.
$(NODE_DEPS): tests/js/package.json tests/js/package-lock.json
	@command -v npm >/dev/null || { echo "make: npm missing; running scripts/install-deps"; sh scripts/install-deps; }
	cd tests/js && npm ci --no-audit --no-fund --loglevel=error

tests: all $(TESTBIN) $(TOOLBIN) $(FUZZREPLAY) $(NODE_DEPS)

# The builds of check, check-tsan, check-asan and fuzz on every CPU when
# make itself was given no -j (CI runs them one after the other, each
# build otherwise on one CPU of the machine's).
NPROC := $(shell nproc 2>/dev/null || echo 2)
PAR = $(if $(filter -j% --jobserver%,$(MAKEFLAGS)),,-j$(NPROC))
check:
	@$(MAKE) --no-print-directory $(PAR) tests
	@sh tests/run

example: all $(TOOLBIN)
	sh examples/run

bench: all $(TOOLBIN)
	sh scripts/bench
	sh scripts/bench-pyramid
	sh scripts/bench-play
	sh scripts/bench-tiles
	sh scripts/bench-terrain

install: all
	install -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR) $(DESTDIR)$(MANDIR)/man1 $(DESTDIR)$(MANDIR)/man5
	install -m 644 $(PLUGIN) $(DESTDIR)$(LIBDIR)
	install -m 755 $(PROGS:%=$(B)/%) $(DESTDIR)$(BINDIR)
	install -m 644 $(MAN1) $(DESTDIR)$(MANDIR)/man1
	install -m 644 $(MAN5) $(DESTDIR)$(MANDIR)/man5
	install -d $(DESTDIR)$(MANDIR)/man7
	install -m 644 $(MAN7) $(DESTDIR)$(MANDIR)/man7

clean:
	rm -rf $(B)/lib $(B)/cmd $(B)/tests $(B)/tools $(B)/*.a $(PLUGIN) $(PROGS:%=$(B)/%)

# tilepack and dem2vgis on a real DEM under ThreadSanitizer (a build of
# their own in build-tsan/, the levels on parallel threads).
# dem2vgis and the stages it runs (tests/tsan), not every program
TSAN_PROGS = dem2vgis dem2fqm fqmfilter fqmsolve tilepack vgis-job vgis2terrain
check-tsan:
	$(MAKE) $(PAR) B=build-tsan CFLAGS='-O1 -g -fsanitize=thread' \
	    CXXFLAGS='-O1 -g -fsanitize=thread' LDFLAGS=-fsanitize=thread \
	    $(TSAN_PROGS:%=build-tsan/%)
	sh tests/tsan build-tsan

FUZZ_TIME ?= 60
FZ_FLAGS = -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined \
           -fno-sanitize-recover=undefined
# clang's vptr check needs its C++ runtime, which the C driver that links
# the programs leaves out; the dynamic types checked would be GDAL's.
FZ_CXXFLAGS = $(FZ_FLAGS) -fno-sanitize=vptr
fuzz:
	$(MAKE) $(PAR) B=build-fuzz CC=clang CXX=clang++ \
	    CFLAGS='$(FZ_FLAGS) -fsanitize=fuzzer-no-link' \
	    CXXFLAGS='$(FZ_CXXFLAGS) -fsanitize=fuzzer-no-link' \
	    LDFLAGS='-fsanitize=address,undefined' fuzz-targets
	sh tests/fuzz/run build-fuzz $(FUZZ_TIME) $(FUZZ)

fuzz-targets: all $(FUZZ:%=$(B)/fuzz/fz_%)
$(B)/fuzz/fz_%: tests/fuzz/fz_%.c tests/fuzz/fuzz.c tests/fuzz/fuzz.h \
    $(B)/cmd/cli.o $(call archives,$(FUZZ_USES))
	@mkdir -p $(@D)
	$(CC) $(TESTFLAGS) -Itests/fuzz -Isrc/cmd -fsanitize=fuzzer -o $@ $< \
	    tests/fuzz/fuzz.c $(B)/cmd/cli.o $(call ld,$(FUZZ_USES))

# The whole suite on an AddressSanitizer + UndefinedBehaviorSanitizer build
# of its own (build-asan/): any report fails the test that caused it. It
# runs several times slower: TL_QUICK leaves the largest DEM out of the
# heaviest tests (tests/lib.sh).
ASAN_FLAGS = -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined \
             -fno-sanitize-recover=undefined
check-asan:
	$(MAKE) $(PAR) B=build-asan CFLAGS='$(ASAN_FLAGS)' CXXFLAGS='$(ASAN_FLAGS)' \
	    LDFLAGS='-fsanitize=address,undefined' tests
	ASAN_OPTIONS=abort_on_error=0:exitcode=66:suppressions=$(CURDIR)/tests/asan.supp \
	LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp \
	UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:exitcode=66 \
	TL_QUICK=1 TL_BUILD=build-asan sh tests/run

-include $(shell find $(B) -name '*.d' 2>/dev/null)

.PHONY: all print-layers tests check check-tsan check-asan fuzz fuzz-targets example bench install clean
.SECONDARY:
