# terrain LOD toolchain: dem2fqm fqmfilter fqmsolve tilepack tileplay
# make            build everything (installs missing Debian packages first)
# make check      build and run every test
# make example    build a pyramid from the default example DEM
# make bench      measure errors, speed and memory on ../shared/data
#                 (scripts/bench: the filters; scripts/bench-pyramid: DEM to
#                 pyramid, triangle counts and real errors)
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

# Resolved when a recipe runs, i.e. after $(B)/.deps has installed them.
PKGS    := OpenEXR gdal libtiff-4 geographiclib OpenImageIO jansson proj egl epoxy glfw3 stb
PKGCF    = $(shell pkg-config --cflags $(PKGS))
PKGLIBS  = $(shell pkg-config --libs $(PKGS)) -lOpenEXRCore-3_1
ALLCFLAGS = -std=c11 -D_DEFAULT_SOURCE $(WARN) $(CFLAGS) $(PKGCF) -Isrc/lib \
            -DTL_LIBDIR='"$(LIBDIR)"'
ALLCXXFLAGS = -std=c++17 -Wall -Wextra $(CXXFLAGS) $(PKGCF) -Isrc/lib
LDLIBS   = -Wl,--as-needed $(PKGLIBS) -lz -lstdc++ -lm -lpthread -ldl

PROGS   := dem2fqm fqmfilter fqmsolve tilepack tileplay tilecheck
LIBC    := $(wildcard src/lib/*.c)
# OpenImageIO costs 130 MB of RSS just by being linked (260 shared libraries):
# it lives in a plugin loaded only for EXR input and PNG output.
PLUGIN  := $(B)/tl_oiio.so
LIBCXX  := $(filter-out src/lib/oiio_plugin.cpp,$(wildcard src/lib/*.cpp))
LIBOBJ  := $(LIBC:src/lib/%.c=$(B)/lib/%.o) $(LIBCXX:src/lib/%.cpp=$(B)/lib/%.o)
TESTC   := $(wildcard tests/t_*.c)
TESTBIN := $(TESTC:tests/%.c=$(B)/tests/%)
TOOLC   := $(wildcard tests/tools/*.c)
TOOLBIN := $(TOOLC:tests/tools/%.c=$(B)/tools/%)
SCRIPTS := dem2vgis
MAN1    := $(PROGS:%=man/%.1) $(SCRIPTS:%=man/%.1)
MAN5    := $(wildcard man/*.5)

all: $(PROGS:%=$(B)/%) $(PLUGIN)

# Install the Debian packages the build needs, once, when one is missing.
$(B)/.deps:
	@mkdir -p $(B)
	@if ! command -v pkg-config >/dev/null || \
	    ! pkg-config --exists $(PKGS) egl epoxy glfw3 libpng || \
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

$(PLUGIN): src/lib/oiio_plugin.cpp src/lib/oiio_plugin.h | $(B)/.deps
	$(CXX) -shared -fPIC $(ALLCXXFLAGS) -o $@ $< $(shell pkg-config --libs OpenImageIO)

$(B)/libtl.a: $(LIBOBJ)
	rm -f $@
	ar rcs $@ $^

$(B)/%.o: src/%.c | $(B)/.deps
	@mkdir -p $(@D)
	$(CC) $(ALLCFLAGS) -MMD -MP -c $< -o $@

$(B)/%: $(B)/%.o $(B)/libtl.a
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $< $(B)/libtl.a $(LDLIBS)

$(B)/tests/%: tests/%.c $(B)/libtl.a
	@mkdir -p $(@D)
	$(CC) $(ALLCFLAGS) $(LDFLAGS) -o $@ $< $(B)/libtl.a $(LDLIBS)

$(B)/tools/%: tests/tools/%.c $(B)/libtl.a
	@mkdir -p $(@D)
	$(CC) $(ALLCFLAGS) $(LDFLAGS) -o $@ $< $(B)/libtl.a $(LDLIBS)

check: all $(TESTBIN) $(TOOLBIN)
	@sh tests/run

example: all $(TOOLBIN)
	sh examples/run

bench: all $(TOOLBIN)
	sh scripts/bench
	sh scripts/bench-pyramid
	sh scripts/bench-play

install: all
	install -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR) $(DESTDIR)$(MANDIR)/man1 $(DESTDIR)$(MANDIR)/man5
	install -m 644 $(PLUGIN) $(DESTDIR)$(LIBDIR)
	install -m 755 $(PROGS:%=$(B)/%) $(SCRIPTS:%=scripts/%) $(DESTDIR)$(BINDIR)
	install -m 644 $(MAN1) $(DESTDIR)$(MANDIR)/man1
	install -m 644 $(MAN5) $(DESTDIR)$(MANDIR)/man5

clean:
	rm -rf $(B)/lib $(B)/tests $(B)/tools $(B)/*.o $(B)/*.d $(B)/libtl.a $(PLUGIN) $(PROGS:%=$(B)/%)

# tilepack and dem2vgis on a real DEM under ThreadSanitizer (a build of
# their own in build-tsan/, the levels on parallel threads).
check-tsan:
	$(MAKE) B=build-tsan CFLAGS='-O1 -g -fsanitize=thread' \
	    CXXFLAGS='-O1 -g -fsanitize=thread' LDFLAGS=-fsanitize=thread all
	sh tests/tsan build-tsan

-include $(shell find $(B) -name '*.d' 2>/dev/null)

.PHONY: all check check-tsan example bench install clean
.SECONDARY:
