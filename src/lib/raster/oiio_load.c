/* oiio_load.c - finds and loads the OpenImageIO plugin tl_oiio.so, for
 * the DEM reader (EXR input) and the viewer (PNG output) alike. */
#include <dlfcn.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "raster/oiio_plugin.h"

#ifndef TL_LIBDIR
#define TL_LIBDIR "/usr/local/lib/terrain-lod"
#endif

/* A plugin that exists but fails to load explains more than a missing
 * one: its message wins. */
static void *
try_plugin(const char *path, char *why, size_t n)
{
	void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);

	if (h == NULL && (why[0] == '\0' || access(path, F_OK) == 0)) {
		const char *m = dlerror();
		size_t k = strlen(m = m ? m : path);
		k = k < n ? k : n - 1; /* a cut message beats none */
		memcpy(why, m, k);
		why[k] = '\0';
	}
	return h;
}

/* $TL_OIIO_PLUGIN, else beside the executable, else in ../lib/terrain-lod
 * from it, else TL_LIBDIR. The plugin
 * stays loaded: unloading OpenImageIO (static state, threads) is unsafe,
 * and dlopen counts references, so loading it again is cheap. */
static const tl_oiio_api *
find(char *why, size_t n)
{
	const char *env = getenv("TL_OIIO_PLUGIN");
	char exe[PATH_MAX], *slash;
	const tl_oiio_api *api;
	tl_oiio_entry_fn f;
	ssize_t len;
	void *h = NULL;

	if (env != NULL && *env != '\0') {
		h = try_plugin(env, why, n);
	} else {
		len = readlink("/proc/self/exe", exe, sizeof exe - 16);
		if (len > 0) {
			exe[len] = '\0';
			if ((slash = strrchr(exe, '/')) != NULL) {
				strcpy(slash + 1, "tl_oiio.so");
				h = try_plugin(exe, why, n);
			}
			/* an installed tree moved as a whole: bin/../lib */
			if (h == NULL && slash != NULL && (size_t)(slash - exe) +
			    sizeof "/../lib/terrain-lod/tl_oiio.so" <= sizeof exe) {
				strcpy(slash, "/../lib/terrain-lod/tl_oiio.so");
				h = try_plugin(exe, why, n);
			}
		}
		if (h == NULL)
			h = try_plugin(TL_LIBDIR "/tl_oiio.so", why, n);
	}
	if (h == NULL)
		return NULL;
	*(void **)&f = dlsym(h, TL_OIIO_ENTRY);
	if (f == NULL || (api = f()) == NULL || api->abi != TL_OIIO_ABI) {
		snprintf(why, n, "tl_oiio.so: not a compatible plugin");
		return NULL;
	}
	return api;
}

const tl_oiio_api *
tl_oiio_load(char *why, size_t n)
{
	if (n > 0)
		why[0] = '\0';
	return find(why, n);
}
