/* t_oiio_plugin - the OpenImageIO plugin and its loader (oiio_plugin.h,
 * oiio_load.c): found through $TL_OIIO_PLUGIN, of the right ABI, a PNG
 * written with write_u8 read back sample for sample, errors as strings;
 * a missing plugin, a library that is not one, and a file that is not a
 * library each explained. The plugin is the one of the build under test:
 * BUILD/tl_oiio.so for this program's BUILD/tests/raster/t_oiio_plugin. */
#include "raster/oiio_plugin.h"
#include "tap.h"
#include "tmpdir.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static char dir[PATH_MAX / 2], so[PATH_MAX];

static const char *
tmp(const char *name)
{
	return tmpdir_join(dir, name);
}

/* The build directory: this program's path up to "/tests/". */
static void
find_plugin(void)
{
	char exe[PATH_MAX - 32] = "";
	ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
	char *t;

	if (n > 0)
		exe[n] = '\0';
	if ((t = strstr(exe, "/tests/")) != NULL)
		*t = '\0';
	else
		snprintf(exe, sizeof exe, "build");
	snprintf(so, sizeof so, "%s/tl_oiio.so", exe);
}

static void
test_png(const tl_oiio_api *api)
{
	enum { W = 5, H = 3, N = 3 };
	unsigned char px[W * H * N], back[W * H * N];
	tl_oiio_info info;
	tl_oiio_img *img;
	char err[256] = "";
	int r;

	for (int k = 0; k < W * H * N; k++)
		px[k] = (unsigned char)(k * 37 + 11);
	r = api->write_u8(tmp("p.png"), "png", W, H, N, px, err, sizeof err);
	ok(r == 0 && access(tmp("p.png"), F_OK) == 0, "write_u8: a 5x3 RGB "
	    "PNG %s", err);
	img = api->open(tmp("p.png"), &info, err, sizeof err);
	ok(img != NULL && info.width == W && info.height == H &&
	    info.nchannels == N && info.type == TL_PX_U8 && info.bits == 8 &&
	    strcmp(info.format, "png") == 0, "open: its size, 3 channels, "
	    "8-bit, format png %s", err);
	memset(back, 0, sizeof back);
	r = img != NULL ? api->read_rows(img, 0, H, N, back, err,
	    sizeof err) : -1;
	ok(r == 0 && memcmp(px, back, sizeof px) == 0, "read_rows: the "
	    "samples as written, top row first %s", err);
	if (img != NULL)
		api->close(img);
	err[0] = '\0';
	ok(api->open(tmp("none.png"), &info, err, sizeof err) == NULL &&
	    err[0] != '\0', "open: a missing file, with a reason (%s)", err);
	err[0] = '\0';
	ok(api->write_u8(tmp("no/such/dir.png"), "png", W, H, N, px, err,
	    sizeof err) < 0 && err[0] != '\0', "write_u8: an impossible path, "
	    "with a reason (%s)", err);
	unlink(tmp("p.png"));
}

/* tl_oiio_load with $TL_OIIO_PLUGIN set to path, in a child (a plugin
 * once loaded stays); the reason comes back through a pipe. */
static int
load_as(const char *path, char *why, size_t n)
{
	int fd[2], st;
	ssize_t got;
	pid_t pid;

	if (pipe(fd) != 0)
		return -1;
	fflush(stdout);
	if ((pid = fork()) == 0) {
		char w[512] = "";
		const tl_oiio_api *api;
		close(fd[0]);
		setenv("TL_OIIO_PLUGIN", path, 1);
		api = tl_oiio_load(w, sizeof w);
		if (write(fd[1], w, strlen(w)) < 0)
			_exit(3);
		_exit(api != NULL ? 0 : 1);
	}
	close(fd[1]);
	got = read(fd[0], why, n - 1);
	why[got > 0 ? got : 0] = '\0';
	close(fd[0]);
	waitpid(pid, &st, 0);
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static void
test_failures(void)
{
	char why[512];
	FILE *f;

	ok(load_as(tmp("nowhere.so"), why, sizeof why) == 1 &&
	    strstr(why, "nowhere.so") != NULL, "a missing plugin: NULL, the "
	    "reason names it (%s)", why);
	ok(load_as("libm.so.6", why, sizeof why) == 1 &&
	    strcmp(why, "tl_oiio.so: not a compatible plugin") == 0,
	    "a library without the entry point: not a compatible plugin");
	f = fopen(tmp("text.so"), "w");
	fputs("not a library\n", f);
	fclose(f);
	ok(load_as(tmp("text.so"), why, sizeof why) == 1 && why[0] != '\0' &&
	    strstr(why, "not a compatible") == NULL, "a file that is no "
	    "library: the loader's own reason (%s)", why);
	unlink(tmp("text.so"));
}

int
main(void)
{
	const char *t = getenv("TMPDIR");
	const tl_oiio_api *api;
	char why[512];

	snprintf(dir, sizeof dir, "%s/t_oiio.XXXXXX", t && *t ? t : "/tmp");
	if (mkdtemp(dir) == NULL) {
		perror(dir);
		return 1;
	}
	find_plugin();
	test_failures(); /* first: forks before OpenImageIO starts threads */
	setenv("TL_OIIO_PLUGIN", so, 0);
	api = tl_oiio_load(why, sizeof why);
	ok(api != NULL && api->abi == TL_OIIO_ABI && api->write_u8 != NULL,
	    "tl_oiio_load: %s, ABI %d %s", getenv("TL_OIIO_PLUGIN"),
	    TL_OIIO_ABI, api ? "" : why);
	if (api != NULL)
		test_png(api);
	rmdir(dir);
	return tap_done();
}
