/* fly.c - a scripted flight (see fly.h). */
#include "play/fly.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int
fly_circle(const world *w, fly_key *k)
{
	double a[3], b[3], r, alt, drop;
	int n = 0;

	world_pos(w, 0, 0, 0, 0, 0, a);
	world_pos(w, w->ix.size0[0] - 1, w->ix.size0[1] - 1, 0, 0, 0, b);
	r = 0.35 * fmin(fabs(b[0] - a[0]), fabs(b[1] - a[1]));
	alt = w->zmax + r * tan(10 * M_PI / 180);
	drop = r * tan(10 * M_PI / 180);
	for (int q = 0; q <= 36; q++, n++) {
		double t = -M_PI / 2 + 2 * M_PI * q / 36;
		k[n].eye[0] = r * cos(t), k[n].eye[1] = r * sin(t);
		k[n].eye[2] = alt;
		k[n].target[0] = k[n].target[1] = 0;
		k[n].target[2] = alt - drop;
	}
	assert(n <= FLY_MAXKEY);
	return n;
}

int
fly_read_path(const char *path, fly_key *k, tl_err *e)
{
	FILE *f = fopen(path, "r");
	char line[1024];
	int n = 0, no = 0;

	if (f == NULL)
		return tl_failsys(e, "%s", path);
	while (fgets(line, sizeof line, f) != NULL) {
		fly_key *q = &k[n];
		char *s = line + strspn(line, " \t");
		no++;
		if (*s == '#' || *s == '\n' || *s == '\0')
			continue;
		if (n == FLY_MAXKEY || sscanf(s, "%lf %lf %lf %lf %lf %lf",
		    &q->eye[0], &q->eye[1], &q->eye[2], &q->target[0],
		    &q->target[1], &q->target[2]) != 6) {
			fclose(f);
			return tl_fail(e, "%s:%d: expected \"ex ey ez tx ty tz\" "
			    "(at most %d lines)", path, no, FLY_MAXKEY);
		}
		n++;
	}
	fclose(f);
	if (n == 0)
		return tl_fail(e, "%s: no keyframes", path);
	return n;
}

void
fly_at(const fly_key *k, int nk, int f, int n, double eye[3],
    double target[3])
{
	double s = n > 1 ? (double)f / (n - 1) * (nk - 1) : 0, t;
	int a = (int)floor(s);

	assert(nk >= 1 && f >= 0 && f < n);
	if (a >= nk - 1)
		a = nk > 1 ? nk - 2 : 0;
	t = nk > 1 ? s - a : 0;
	for (int q = 0; q < 3; q++) {
		const fly_key *b = &k[nk > 1 ? a + 1 : a];
		eye[q] = k[a].eye[q] + t * (b->eye[q] - k[a].eye[q]);
		target[q] = k[a].target[q] + t * (b->target[q] - k[a].target[q]);
	}
}

typedef struct {
	const fly_key *k;
	int nk;
	double sum, max, tris; /* frame times (ms) and triangles, summed */
} flight;

/* Frame f: chosen and drawn as the window would, the missing blocks
 * loading behind; with --wait (and always for frame 0, the first
 * complete picture) after waiting for them. ms is the drawing's time:
 * choosing, drawing and glFinish; wait_ms the waiting's. */
static int
frame(scene *sc, const scene_opts *so, const fly_opts *o, int f,
    flight *fl, tl_err *e)
{
	double t = scene_clock(), tw, ms, eye[3], target[3];
	cache_stats cs;

	fly_at(fl->k, fl->nk, f, o->frames, eye, target);
	camera_look(&sc->cam, &sc->w, eye, target);
	if ((f == 0 || o->wait) && scene_settle(sc, so->pixels, e) < 0)
		return -1;
	tw = scene_clock();
	scene_choose(sc, so->pixels);
	if (scene_draw(sc, &so->style, e) < 0)
		return -1;
	gl_ctx_present(sc->g);
	ms = (scene_clock() - tw) * 1000;
	cache_get_stats(sc->k, &cs);
	if (cs.error[0] != '\0')
		return tl_fail(e, "%s", cs.error);
	printf("%d %.2f %.2f %ld %ld %zu %ld\n", f, ms, (tw - t) * 1000,
	    sc->st.tris, sc->st.blocks, cs.bytes, sc->misses);
	fl->sum += ms, fl->tris += sc->st.tris;
	fl->max = fmax(fl->max, ms);
	return 0;
}

static int
flight_run(scene *sc, const scene_opts *so, const fly_opts *o, double t0,
    flight *fl, tl_err *e)
{
	double first = 0;
	cache_stats cs;

	printf("# frame ms wait_ms triangles blocks cache_bytes missing\n");
	for (int f = 0; f < o->frames; f++) {
		if (frame(sc, so, o, f, fl, e) < 0)
			return -1;
		if (f == 0)
			first = scene_clock() - t0;
	}
	cache_get_stats(sc->k, &cs);
	printf("# %d frames at %.3g px, %dx%d: frame time mean %.2f ms, max "
	    "%.2f ms; triangles mean %.0f; first frame %.3f s; cache peak "
	    "%zu of %zu bytes (%.1f of %.1f MB), %ld loads, %ld evictions\n",
	    o->frames, so->pixels, so->width, so->height, fl->sum / o->frames,
	    fl->max, fl->tris / o->frames, first, cs.peak, cs.cap,
	    cs.peak / 1048576.0, cs.cap / 1048576.0, cs.loads, cs.evictions);
	return 0;
}

int
fly_run(const scene_opts *so, const fly_opts *o, double t0, tl_err *e)
{
	fly_key *k;
	flight fl = { NULL, 0, 0, 0, 0 };
	scene sc;
	int r = -1;

	if ((k = tl_alloc(FLY_MAXKEY, sizeof *k, e)) == NULL)
		return -1;
	if (scene_open(&sc, so, 1, e) < 0) {
		free(k);
		return -1;
	}
	fl.k = k;
	fl.nk = o->path != NULL ? fly_read_path(o->path, k, e) :
	    fly_circle(&sc.w, k);
	if (fl.nk > 0)
		r = flight_run(&sc, so, o, t0, &fl, e);
	scene_close(&sc);
	free(k);
	return r;
}
