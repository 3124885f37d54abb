/* t_fly - the scripted flight: the built-in circle, frames spread over
 * keyframes, path files and their errors, and a flight's output (a line
 * a frame, nothing missing when it waits, the summary). */
#include <math.h>

#include "play/fly.h"
#include "fixture.h"

static void
test_circle(const world *w)
{
	fly_key k[FLY_MAXKEY];
	int n = fly_circle(w, k), same = 1;

	ok(n == 37, "the circle: 37 keyframes");
	for (int a = 0; a < 3; a++)
		same &= fabs(k[0].eye[a] - k[36].eye[a]) < 1e-6;
	ok(same && fabs(k[0].eye[0]) < 1e-6 && k[0].eye[1] < 0 &&
	    k[9].eye[0] > 0, "one turn from the south, counter-clockwise");
	ok(k[0].eye[2] > w->zmax && k[0].target[2] < k[0].eye[2] &&
	    k[0].target[0] == 0 && k[0].target[1] == 0,
	    "above the highest point, looking down at the centre");
}

static void
test_at(void)
{
	fly_key k[2] = { { { 0, 0, 0 }, { 1, 1, 1 } },
		{ { 10, 20, 30 }, { 2, 2, 2 } } };
	double e[3], t[3];

	fly_at(k, 2, 0, 5, e, t);
	ok(e[0] == 0 && t[0] == 1, "frame 0 is the first keyframe");
	fly_at(k, 2, 4, 5, e, t);
	ok(e[1] == 20 && t[2] == 2, "the last frame the last keyframe");
	fly_at(k, 2, 2, 5, e, t);
	ok(e[0] == 5 && e[2] == 15 && t[1] == 1.5, "linear between them");
	fly_at(k, 1, 3, 5, e, t);
	ok(e[0] == 0 && t[0] == 1, "one keyframe: it, always");
	fly_at(k, 2, 0, 1, e, t);
	ok(e[0] == 0, "one frame: the first keyframe");
}

static const char *
write_file(const char *name, const char *text)
{
	static char path[512];
	FILE *f;

	fx_dir(name, path, sizeof path);
	if ((f = fopen(path, "w")) != NULL) {
		fputs(text, f);
		fclose(f);
	}
	return path;
}

static void
test_path(void)
{
	fly_key k[FLY_MAXKEY];
	tl_err e;
	const char *p;

	p = write_file("ok.path", "# eye target\n\n  1 2 3 4 5 6\n"
	    "7 8 9 10 11 12\n");
	ok(fly_read_path(p, k, &e) == 2 && k[1].target[2] == 12,
	    "comments and blank lines skipped, two keyframes");
	p = write_file("bad.path", "1 2 3 4 5 6\n\n1 2 3\n");
	ok(fly_read_path(p, k, &e) < 0 && strstr(e.msg, "bad.path:3: "
	    "expected \"ex ey ez tx ty tz\"") != NULL, "a short line: %s",
	    e.msg);
	p = write_file("empty.path", "# nothing\n");
	ok(fly_read_path(p, k, &e) < 0 && strstr(e.msg, ": no keyframes") !=
	    NULL, "no keyframes: %s", e.msg);
	fx_dir("none.path", (char *)p, 512);
	ok(fly_read_path(p, k, &e) < 0 && strstr(e.msg, "none.path: ") !=
	    NULL, "no file: %s", e.msg);
}

/* A flight of 4 frames that wait: a line each, nothing missing. */
static void
test_run(void)
{
	scene_opts so;
	fly_opts o = { 4, NULL, 1 };
	char dir[512], out[512], line[1024];
	FILE *f;
	tl_err e;
	int fd, r, frames = 0, missing = 0;

	scene_opts_init(&so, "t_fly");
	so.width = 160, so.height = 120;
	fx_dir("bt", dir, sizeof dir), fx_dir("fly.out", out, sizeof out);
	so.dir = dir;
	fd = fx_redirect(1, out);
	r = fly_run(&so, &o, scene_clock(), &e);
	fx_restore(1, fd);
	ok(r == 0, "a flight of 4 frames");
	if ((f = fopen(out, "r")) != NULL) {
		long fr, tris, blocks, miss;
		double ms, wait;
		size_t bytes;
		while (fgets(line, sizeof line, f) != NULL)
			if (sscanf(line, "%ld %lf %lf %ld %ld %zu %ld", &fr, &ms,
			    &wait, &tris, &blocks, &bytes, &miss) == 7)
				frames++, missing += miss != 0 || tris <= 0;
		fclose(f);
	}
	ok(frames == 4 && missing == 0, "a line a frame, every block there "
	    "(%d lines)", frames);
	ok(fx_grep(out, "# 4 frames at 1 px, 160x120: frame time mean ", line,
	    sizeof line) == 0 && strstr(line, " loads, 0 evictions") != NULL,
	    "the summary: %.60s...", line);
}

int
main(int argc, char **argv)
{
	world w;
	gl_ctx *g;

	(void)argc;
	if (fx_init(argv[0], "t_fly") < 0)
		return 1;
	ok(fx_make("bigtujunga.tif", "bt", "") == 0,
	    "pyramid of bigtujunga.tif");
	fx_world(&w, "bt");
	test_circle(&w);
	world_close(&w);
	test_at();
	test_path();
	if ((g = fx_headless(16, 16)) != NULL) {
		gl_ctx_close(g);
		test_run();
	}
	fx_done();
	return tap_done();
}
