/* t_shot - one picture: a PNG written, the same bytes twice, the probe
 * line, the readout drawn, errors (no pyramid, a probe outside, an
 * unwritable image) leaving no file behind. */
#include <sys/stat.h>

#include "play/shot.h"
#include "fixture.h"

static int
same_file(const char *a, const char *b)
{
	char cmd[1200];

	snprintf(cmd, sizeof cmd, "cmp -s '%s' '%s'", a, b);
	return system(cmd) == 0;
}

static int
exists(const char *path)
{
	struct stat st;

	return stat(path, &st) == 0;
}

static void
test_pictures(scene_opts *so)
{
	shot_opts o = { 0 };
	char a[512], b[512], c[512], sig[8] = { 0 };
	tl_err e;
	FILE *f;

	fx_dir("a.png", a, sizeof a), fx_dir("b.png", b, sizeof b);
	fx_dir("c.png", c, sizeof c);
	o.path = a;
	ok(shot_run(so, &o, scene_clock(), &e) == 0, "a shot");
	if ((f = fopen(a, "rb")) != NULL) {
		if (fread(sig, 1, 8, f) != 8)
			sig[0] = 0;
		fclose(f);
	}
	ok(memcmp(sig, "\x89PNG\r\n\x1a\n", 8) == 0, "a PNG");
	o.path = b;
	ok(shot_run(so, &o, scene_clock(), &e) == 0 && same_file(a, b),
	    "the same shot twice, the same bytes");
	o.path = c, o.readout = 1;
	ok(shot_run(so, &o, scene_clock(), &e) == 0 && !same_file(a, c),
	    "--readout draws over it");
}

static void
test_probe(scene_opts *so)
{
	shot_opts o = { 0 };
	char out[512], img[512], line[1024];
	tl_err e;
	int fd, r;

	fx_dir("probe", out, sizeof out), fx_dir("p.png", img, sizeof img);
	o.path = img, o.has_probe = 1, o.probe[0] = 300, o.probe[1] = 200;
	fd = fx_redirect(1, out);
	r = shot_run(so, &o, scene_clock(), &e);
	fx_restore(1, fd);
	ok(r == 0 && fx_grep(out, "probe 300,200: height ", line,
	    sizeof line) == 0 && strstr(line, ", pixel ") != NULL &&
	    strstr(line, ", colour ") != NULL, "the probe line: %.70s", line);
	o.probe[0] = -1;
	ok(shot_run(so, &o, scene_clock(), &e) < 0 && strncmp(e.msg,
	    "--probe -1,200: outside the ", 28) == 0, "a probe outside: %s",
	    e.msg);
}

static void
test_errors(scene_opts *so)
{
	shot_opts o = { 0 };
	char img[512], dir[512];
	unsigned char rgb[16 * 16 * 3] = { 0 };
	tl_err e;

	fx_dir("none.png", img, sizeof img);
	fx_dir("none", dir, sizeof dir);
	so->dir = dir;
	o.path = img;
	ok(shot_run(so, &o, scene_clock(), &e) < 0 && !exists(img),
	    "no pyramid: %s; no picture left", e.msg);
	fx_dir("no/such/dir.png", img, sizeof img);
	ok(shot_write(img, 16, 16, rgb, &e) < 0 && !exists(img),
	    "an unwritable image: %s", e.msg);
}

int
main(int argc, char **argv)
{
	scene_opts so;
	char dir[512];
	gl_ctx *g;

	(void)argc;
	if (fx_init(argv[0], "t_shot") < 0)
		return 1;
	ok(fx_make("bigtujunga.tif", "bt", "") == 0,
	    "pyramid of bigtujunga.tif");
	if ((g = fx_headless(16, 16)) != NULL) {
		gl_ctx_close(g);
		scene_opts_init(&so, "t_shot");
		so.width = 200, so.height = 150;
		fx_dir("bt", dir, sizeof dir);
		so.dir = dir;
		test_pictures(&so);
		test_probe(&so);
		test_errors(&so);
	}
	fx_done();
	return tap_done();
}
