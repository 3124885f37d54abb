/* t_window - the window, under Xvfb when there is no display (xvfb-run
 * runs this test again inside one): frames drawn, the --stats line at
 * the end; a missing pyramid. Skipped without a display or xvfb-run. */
#include "play/window.h"
#include "fixture.h"

static void
test_frames(void)
{
	scene_opts so;
	window_opts o = { 5, 1 };
	char dir[512], err[512], line[1024];
	tl_err e;
	int fd, r;

	scene_opts_init(&so, "t_window");
	so.width = 320, so.height = 240;
	fx_dir("bt", dir, sizeof dir), fx_dir("err", err, sizeof err);
	so.dir = dir;
	fd = fx_redirect(2, err);
	r = window_run(&so, &o, scene_clock(), &e);
	fx_restore(2, fd);
	if (r < 0 && strstr(e.msg, "cannot open a window") != NULL) {
		ok(1, "# SKIP %s", e.msg);
		return;
	}
	ok(r == 0, "5 frames in a window");
	ok(fx_grep(err, "stats: ", line, sizeof line) == 0 &&
	    strstr(line, " triangles, ") != NULL, "the stats line: %.60s...",
	    line);
	fx_dir("none", dir, sizeof dir);
	ok(window_run(&so, &o, scene_clock(), &e) < 0 &&
	    strstr(e.msg, "index.json") != NULL, "no pyramid: %s", e.msg);
}

int
main(int argc, char **argv)
{
	(void)argc;
	if (getenv("DISPLAY") == NULL && getenv("TL_XVFB") == NULL &&
	    system("command -v xvfb-run >/dev/null && command -v xauth "
	    ">/dev/null") == 0) {
		setenv("TL_XVFB", "1", 1);
		execlp("xvfb-run", "xvfb-run", "-a", argv[0], (char *)NULL);
	}
	if (getenv("DISPLAY") == NULL) {
		ok(1, "# SKIP no display and no xvfb-run: the window untested");
		return tap_done();
	}
	if (fx_init(argv[0], "t_window") < 0)
		return 1;
	ok(fx_make("bigtujunga.tif", "bt", "") == 0,
	    "pyramid of bigtujunga.tif");
	test_frames();
	fx_done();
	return tap_done();
}
