/* tileplay - the VGIS pyramid's player: an interactive OpenGL view of a
 * pyramid (GLFW), headless screenshots and scripted flights (EGL, no
 * display needed), and --verify, an alias of tilecheck(1). Options into
 * one struct, each checked against the mode it belongs to, then the
 * mode's work function (play/window.h, shot.h, fly.h; verify.h). */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "play/fly.h"
#include "play/shot.h"
#include "play/window.h"
#include "verify/verify.h"

enum { WINDOW = 1, SHOT = 2, FLY = 4, VERIFY = 8, NMODE = 4 };
#define CAMERA (WINDOW | SHOT)        /* where the camera is the user's */
#define PLAYER (WINDOW | SHOT | FLY)  /* where something is drawn */

static const char *mode_names[NMODE] = { "the window", "--shot", "--fly",
	"--verify" };

enum { OPT_VERIFY = 256, OPT_DEM, OPT_TAU, OPT_SHOT, OPT_FLY, OPT_PATH,
	OPT_WAIT, OPT_FRAMES, OPT_STATS, OPT_PROBE, OPT_READOUT, OPT_VIEW,
	OPT_EYE, OPT_TARGET, OPT_SIZE, OPT_PIXELS, OPT_COLOR, OPT_WIRE,
	OPT_NOSKIRTS, OPT_NOLIGHT, OPT_BACKGROUND, OPT_CACHE };

/* Every option: its name in messages ("--x" long, "-x" short), getopt's
 * value, whether it takes an argument, and the modes it belongs to. */
static const struct opt {
	const char *name;
	int val, arg, modes;
} opts[] = {
	{ "--verify", OPT_VERIFY, 1, VERIFY },
	{ "--dem", OPT_DEM, 1, VERIFY },
	{ "--tau", OPT_TAU, 1, VERIFY },
	{ "-D", 'D', 1, VERIFY }, { "-e", 'e', 1, VERIFY },
	{ "-H", 'H', 1, VERIFY }, { "-N", 'N', 1, VERIFY },
	{ "-n", 'n', 1, VERIFY }, { "-s", 's', 1, VERIFY },
	{ "--shot", OPT_SHOT, 1, SHOT },
	{ "--fly", OPT_FLY, 1, FLY },
	{ "--path", OPT_PATH, 1, FLY },
	{ "--wait", OPT_WAIT, 0, FLY },
	{ "--frames", OPT_FRAMES, 1, WINDOW },
	{ "--stats", OPT_STATS, 0, WINDOW | SHOT },
	{ "--probe", OPT_PROBE, 1, SHOT },
	{ "--readout", OPT_READOUT, 0, SHOT },
	{ "--view", OPT_VIEW, 1, CAMERA },
	{ "--eye", OPT_EYE, 1, CAMERA },
	{ "--target", OPT_TARGET, 1, CAMERA },
	{ "--size", OPT_SIZE, 1, PLAYER },
	{ "--pixels", OPT_PIXELS, 1, PLAYER },
	{ "--color", OPT_COLOR, 1, PLAYER },
	{ "--wire", OPT_WIRE, 0, PLAYER },
	{ "--no-skirts", OPT_NOSKIRTS, 0, PLAYER },
	{ "--no-light", OPT_NOLIGHT, 0, PLAYER },
	{ "--background", OPT_BACKGROUND, 1, PLAYER },
	{ "--cache", OPT_CACHE, 1, PLAYER },
};
#define NOPT ((int)(sizeof opts / sizeof opts[0]))

typedef struct {
	int seen[NOPT];    /* the order options came in (1, 2, ...), 0 not */
	int nseen;
	int mode;
	vf_args chk;       /* --verify */
	scene_opts view;   /* the player's */
	shot_opts shot;
	fly_opts fly;
	window_opts win;
	int size_set;
} options;

static void
usage_text(char *buf, size_t n, const char *prog)
{
	int w = (int)strlen(prog) + 8; /* "usage: prog " */

	snprintf(buf, n, "--verify dir [--dem dem] [--tau t,...] [-D datum] "
	    "[-e encoding]\n"
	    "%*s[-H datum] [-N nodata] [-n name] [-s dx[,dy]]\n"
	    "       %s [camera] [drawing] [--frames n] [--stats] dir\n"
	    "       %s --shot file [camera] [drawing] [--stats] [--readout]\n"
	    "%*s[--probe i,j] dir\n"
	    "       %s --fly n [--path file] [--wait] [drawing] dir\n"
	    "  --verify dir    check the pyramid in dir as tilecheck(1) does\n"
	    "  --dem dem       the DEM it was made from: check its errors too\n"
	    "  --tau t,...     tolerances in metres instead of each level's "
	    "sweep\n"
	    "  -D, -e, -H, -N, -n, -s  how to read the DEM, as for "
	    "dem2fqm(1)\n"
	    "  dir             the pyramid to show in a window (keys: "
	    "tileplay(1))\n"
	    "  --shot file     render one picture headless (EGL) into a PNG\n"
	    "  --fly n         fly n frames headless along a path, print "
	    "times and triangles\n"
	    "camera (the window, --shot):\n"
	    "  --view name     overview (straight down) or oblique (from "
	    "the south-west)\n"
	    "  --eye x,y,z --target x,y,z  a camera in world metres instead\n"
	    "drawing (the window, --shot, --fly):\n"
	    "  --size WxH      frame size in pixels (1024x768; headless "
	    "640x480)\n"
	    "  --pixels p      screen-space error tolerance (1; 0: full "
	    "resolution)\n"
	    "  --color mode    height, level or error\n"
	    "  --wire --no-skirts --no-light\n"
	    "  --background r,g,b  clear colour, 0..255\n"
	    "  --cache mb      block cache cap in MB (256)\n"
	    "one mode's own:\n"
	    "  --stats         the window, --shot: a line of statistics on "
	    "stderr\n"
	    "  --readout       --shot: the window's readout over the picture\n"
	    "  --probe i,j     --shot: where DEM sample (i,j) lands and its "
	    "colour\n"
	    "  --path file     --fly: keyframes, one \"ex ey ez tx ty tz\" a "
	    "line\n"
	    "  --wait          --fly: every frame waits for its blocks\n"
	    "  --frames n      the window: exit after n frames\n"
	    "an option of another mode is a usage error\n",
	    w, "", prog, prog, w + 12, "", prog);
}

/* The long options of the table, for getopt_long. */
static void
long_options(struct option *lo)
{
	int n = 0;

	for (int k = 0; k < NOPT; k++)
		if (opts[k].name[1] == '-')
			lo[n++] = (struct option){ opts[k].name + 2,
			    opts[k].arg ? required_argument : no_argument, NULL,
			    opts[k].val };
	memset(&lo[n], 0, sizeof lo[n]);
}

/* Exactly n numbers separated by sep: "x,y,z", "WxH". */
static int
parse_nums(const char *s, int sep, double *v, int n)
{
	char buf[256], *p = buf, *q;

	if (strlen(s) >= sizeof buf)
		return -1;
	strcpy(buf, s);
	for (int k = 0; k < n; k++, p = q + 1) {
		q = k < n - 1 ? strchr(p, sep) : p + strlen(p);
		if (q == NULL)
			return -1;
		*q = '\0';
		if (tl_parse_double(p, &v[k]) < 0)
			return -1;
	}
	return 0;
}

static int
is_int(double v, double lo, double hi)
{
	return v == floor(v) && v >= lo && v <= hi;
}

/* --verify and its options; 0 or the usage status. */
static int
verify_option(const cli *c, options *o, int ch, const char *arg)
{
	tl_err e;

	switch (ch) {
	case OPT_VERIFY: o->chk.dir = arg; return 0;
	case OPT_DEM: o->chk.dem_path = arg; return 0;
	case OPT_TAU:
		if (vf_parse_taus(&o->chk, arg) < 0)
			return cli_bad(c, "--tau %s: expected up to %d numbers "
			    ">= 0, comma-separated", arg, VF_MAXTAU);
		return 0;
	}
	if (dem_option(&o->chk.dem, ch, arg, &e) < 0)
		return cli_bad(c, "%s", e.msg);
	return 0;
}

/* The modes' own options. */
static int
mode_option(cli *c, options *o, int ch, const char *arg)
{
	double v[2];

	switch (ch) {
	case OPT_SHOT: o->shot.path = arg; return 0;
	case OPT_PATH: o->fly.path = arg; return 0;
	case OPT_WAIT: o->fly.wait = 1; return 0;
	case OPT_STATS: o->shot.stats = o->win.stats = 1; return 0;
	case OPT_READOUT: o->shot.readout = 1; return 0;
	case OPT_FLY:
		o->fly.frames = (int)cli_number(c, "--fly", arg, 1, INT_MAX);
		return c->status >= 0 ? c->status : 0;
	case OPT_FRAMES:
		o->win.frames = (int)cli_number(c, "--frames", arg, 1, INT_MAX);
		return c->status >= 0 ? c->status : 0;
	case OPT_PROBE:
		if (parse_nums(arg, ',', v, 2) < 0 || !is_int(v[0], -1e9, 1e9) ||
		    !is_int(v[1], -1e9, 1e9))
			return cli_bad(c, "--probe %s: expected i,j: a level-0 "
			    "column and row", arg);
		o->shot.probe[0] = (int)v[0], o->shot.probe[1] = (int)v[1];
		o->shot.has_probe = 1;
		return 0;
	}
	return -1;
}

/* The camera: --view, --eye, --target. */
static int
camera_option(const cli *c, scene_opts *s, int ch, const char *arg)
{
	int eye = ch == OPT_EYE;

	if (ch == OPT_VIEW) {
		if (!camera_view_known(arg))
			return cli_bad(c, "--view %s: unknown view (overview, "
			    "oblique)", arg);
		s->view = arg;
		return 0;
	}
	if (parse_nums(arg, ',', eye ? s->eye : s->target, 3) < 0)
		return cli_bad(c, "%s %s: expected x,y,z in world metres",
		    eye ? "--eye" : "--target", arg);
	*(eye ? &s->has_eye : &s->has_target) = 1;
	return 0;
}

/* How the frame is drawn and the cache. */
static int
draw_option(cli *c, options *o, int ch, const char *arg)
{
	scene_opts *s = &o->view;
	double v[3];

	switch (ch) {
	case OPT_WIRE: s->style.wire = 1; return 0;
	case OPT_NOSKIRTS: s->style.skirts = 0; return 0;
	case OPT_NOLIGHT: s->style.light = 0; return 0;
	case OPT_SIZE:
		if (parse_nums(arg, 'x', v, 2) < 0 || !is_int(v[0], 16, 16384) ||
		    !is_int(v[1], 16, 16384))
			return cli_bad(c, "--size %s: expected WxH, 16 to 16384 "
			    "pixels", arg);
		s->width = (int)v[0], s->height = (int)v[1], o->size_set = 1;
		return 0;
	case OPT_PIXELS: /* a tolerance of more than a screen: the root */
		s->pixels = cli_real(c, "--pixels", arg, 0, 1e6);
		return c->status >= 0 ? c->status : 0;
	case OPT_COLOR:
		if (gl_style_colour_parse(arg, &s->style.colour) < 0)
			return cli_bad(c, "--color %s: expected height, level or "
			    "error", arg);
		return 0;
	case OPT_BACKGROUND:
		if (parse_nums(arg, ',', v, 3) < 0 || !(v[0] >= 0 && v[0] <= 255 &&
		    v[1] >= 0 && v[1] <= 255 && v[2] >= 0 && v[2] <= 255))
			return cli_bad(c, "--background %s: expected r,g,b, 0 to "
			    "255", arg);
		for (int k = 0; k < 3; k++)
			s->style.background[k] = (float)(v[k] / 255);
		return 0;
	case OPT_CACHE:
		s->cache_mb = cli_real(c, "--cache", arg, 1, 1048576);
		return c->status >= 0 ? c->status : 0;
	}
	return camera_option(c, s, ch, arg);
}

/* Records the option (its first place) and reads its value: 0, or the
 * usage status. */
static int
option(cli *c, options *o, int ch, const char *arg)
{
	int k = 0, r;

	while (k < NOPT && opts[k].val != ch)
		k++;
	if (k == NOPT)
		return cli_usage_error(c);
	if (o->seen[k] == 0)
		o->seen[k] = ++o->nseen;
	if (opts[k].modes == VERIFY)
		return verify_option(c, o, ch, arg);
	if ((r = mode_option(c, o, ch, arg)) >= 0)
		return r;
	return draw_option(c, o, ch, arg);
}

/* "the window, --shot or --fly" */
static void
modes_text(int modes, char *buf, size_t n)
{
	int cnt = 0, i = 0;
	size_t len = 0;

	for (int m = 0; m < NMODE; m++)
		cnt += modes >> m & 1;
	buf[0] = '\0';
	for (int m = 0; m < NMODE && len < n; m++)
		if (modes >> m & 1) {
			len += snprintf(buf + len, n - len, "%s%s", i == 0 ? "" :
			    i == cnt - 1 ? " or " : ", ", mode_names[m]);
			i++;
		}
}

/* The given option that came first among those for which is(k) holds,
 * after the one that came at place `after`; -1 when none. */
static int
first_seen(const options *o, int after, int (*is)(int k, int mode),
    int mode)
{
	int best = -1;

	for (int k = 0; k < NOPT; k++)
		if (o->seen[k] > after && is(k, mode) &&
		    (best < 0 || o->seen[k] < o->seen[best]))
			best = k;
	return best;
}

static int
selects(int k, int mode)
{
	(void)mode;
	return opts[k].val == OPT_VERIFY || opts[k].val == OPT_SHOT ||
	    opts[k].val == OPT_FLY;
}

static int
foreign(int k, int mode)
{
	return !(opts[k].modes & mode);
}

/* The mode the options select (at most one of --verify, --shot, --fly;
 * else the window), then every option given checked against it. */
static int
scope(const cli *c, options *o)
{
	int a = first_seen(o, 0, selects, 0), b, m = 0;
	char modes[128];

	if (a >= 0 && (b = first_seen(o, o->seen[a], selects, 0)) >= 0)
		return cli_bad(c, "%s and %s: one at a time", opts[a].name,
		    opts[b].name);
	o->mode = a >= 0 ? opts[a].modes : WINDOW;
	if ((b = first_seen(o, 0, foreign, o->mode)) < 0)
		return 0;
	while (o->mode != 1 << m)
		m++;
	modes_text(opts[b].modes, modes, sizeof modes);
	return cli_bad(c, "%s: only with %s, not with %s", opts[b].name,
	    modes, mode_names[m]);
}

/* The player's operand and what its options say together. */
static int
player(const cli *c, options *o, int argc, char **argv)
{
	const scene_opts *s = &o->view;

	if (optind != argc - 1)
		return cli_usage_error(c);
	o->view.dir = argv[optind];
	if (s->has_eye && s->has_target && s->eye[0] == s->target[0] &&
	    s->eye[1] == s->target[1] && s->eye[2] == s->target[2])
		return cli_bad(c, "--eye and --target: the same point");
	if (o->mode != WINDOW && !o->size_set)
		o->view.width = 640, o->view.height = 480;
	return 0;
}

int
main(int argc, char **argv)
{
	struct option lo[NOPT + 1];
	double t0 = scene_clock();
	char usage[4096];
	options o;
	cli c;
	tl_err e;
	int ch, r;

	memset(&o, 0, sizeof o);
	cli_init(&c, argv, NULL, 0);
	usage_text(usage, sizeof usage, c.prog);
	c.usage = usage;
	scene_opts_init(&o.view, c.prog);
	long_options(lo);
	while ((ch = cli_next(&c, argc, argv, DEM_OPTS, lo)) != -1)
		if ((r = option(&c, &o, ch, optarg)) != 0)
			return r;
	if (c.status >= 0)
		return c.status;
	if ((r = scope(&c, &o)) != 0)
		return r;
	if (o.mode == VERIFY) {
		if (optind < argc)
			return cli_usage_error(&c);
		/* exit 1 when it cannot check, as it always did */
		return vf_run(&o.chk, c.prog) != 0;
	}
	if ((r = player(&c, &o, argc, argv)) != 0)
		return r;
	if (o.mode == SHOT)
		r = shot_run(&o.view, &o.shot, t0, &e);
	else if (o.mode == FLY)
		r = fly_run(&o.view, &o.fly, t0, &e);
	else
		r = window_run(&o.view, &o.win, t0, &e);
	return cli_exit(&c, r, &e);
}
