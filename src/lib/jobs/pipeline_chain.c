/* pipeline_chain.c - the stages' graphs of a run: the quadric chain
 * (level 0, the filters and a solver per level, or a band of them),
 * tilepack over its vertex maps, and -M, the chain alone (a plan's job). */
#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "jobs/pipeline_impl.h"
#include "base/outfile.h"
#include "qem/fqm.h"

/* A band's columns of level l (-C a,b), of a DEM w columns wide. */
static void
band_cols(const pipeline_opts *o, int w, int l, char *buf, size_t n)
{
	int b = o->band[1] >= w ? geo_level_size(w, l) : o->band[1] >> l;

	snprintf(buf, n, "%d,%d", o->band[0] >> l, b);
}

/* The chain's first stage: dem2fqm writing level 0 into a pipe, whose
 * end to read is *up; a band reads its window (-w) of the filled DEM
 * (-F), a plan's step (vgis-job level0). */
static int
level0(const pipeline_opts *o, graph *g, const char *dem, int w, char *win,
    size_t nwin, int *up, tl_err *e)
{
	words a = { 0 };
	int p[2];

	if (graph_pipe(g, p, e) < 0)
		return -1;
	if (o->fill != NULL || o->band[1] > 0)
		say(&a, "vgis-job"), say(&a, "level0");
	else
		say(&a, "dem2fqm");
	say_demopts(&a, o);
	if (o->name != NULL && strcmp(o->dem, "-") != 0)
		say(&a, "-n"), say(&a, o->name);
	if (o->fill != NULL)
		say(&a, "-F"), say(&a, o->fill);
	if (o->band[1] > 0) {
		long h = pipeline_halo(o->band_levels);
		long x0 = o->band[0] - h, x1 = o->band[1] + h;
		snprintf(win, nwin, "%ld,%ld", x0 < 0 ? 0 : x0, x1 > w ? w : x1);
		say(&a, "-w"), say(&a, win);
	}
	say(&a, dem), say(&a, "-");
	*up = p[0];
	return graph_exec(g, (char *const *)a.w, -1, p[1], e);
}

/* The filter chain and one solver per level, all at once: levels first
 * .. levels-1, from the DEM (first 0) or from the FQM o->from; a band's
 * top filter writes level `levels`' FQM to fpath. */
int
pipeline_quadrics(const pipeline_opts *o, const char *dem, int first,
    int levels, int w, vpath_t *vpath, const char *fpath, meter *m,
    int *status, tl_err *e)
{
	graph *g = graph_new(o->prog, o->bindir, e);
	char cut[MAXLEVELS + 1][32], win[64];
	int band = o->band[1] > 0, up = -1, r = -1;
	words a = { 0 };

	if (g == NULL)
		goto done;
	graph_progress(g, pipeline_progress, m);
	if (o->from == NULL && level0(o, g, dem, w, win, sizeof win, &up,
	    e) < 0)
		goto done;
	for (int l = first; l < levels; l++) {
		/* the level's FQM: the pipe up, or the file o->from */
		const char *src = up < 0 ? o->from : "-";
		int q[2] = { -1, -1 }, f[2] = { -1, -1 }, v, top = l == levels - 1;
		if ((up >= 0 && graph_pipe(g, q, e) < 0) ||
		    (v = graph_open(g, vpath[l], O_WRONLY | O_CREAT | O_EXCL,
		    0600, e)) < 0)
			goto done;
		a.n = 0;
		/* a band's columns (-C): a plan's step */
		if (band)
			say(&a, "vgis-job"), say(&a, "solve");
		else
			say(&a, "fqmsolve");
		say(&a, "-m"), say(&a, o->mode);
		if (o->cut != NULL)
			say(&a, "-r"), say(&a, o->cut);
		if (band)
			band_cols(o, w, l, cut[l], sizeof cut[l]),
			    say(&a, "-C"), say(&a, cut[l]);
		say(&a, src), say(&a, "-");
		if (graph_exec(g, (char *const *)a.w, q[0], v, e) < 0)
			goto done;
		if (top && !band) { /* the top: no filter above it */
			if (up >= 0 && graph_tee(g, up, q[1], -1, e) < 0)
				goto done;
			break;
		}
		if (up >= 0 && (graph_pipe(g, f, e) < 0 ||
		    graph_tee(g, up, q[1], f[1], e) < 0))
			goto done;
		a.n = 0;
		if (top)
			say(&a, "vgis-job"), say(&a, "filter");
		else
			say(&a, "fqmfilter");
		say(&a, "-k"), say(&a, o->kernel);
		if (top)
			band_cols(o, w, l + 1, cut[l + 1], sizeof cut[l + 1]),
			    say(&a, "-C"), say(&a, cut[l + 1]);
		say(&a, src), say(&a, "-");
		if (top) {
			if ((v = graph_open(g, fpath, O_WRONLY | O_CREAT | O_EXCL,
			    0600, e)) < 0 ||
			    graph_exec(g, (char *const *)a.w, f[0], v, e) < 0)
				goto done;
			break;
		}
		if (graph_pipe(g, q, e) < 0 ||
		    graph_exec(g, (char *const *)a.w, f[0], q[1], e) < 0)
			goto done;
		up = q[0];
	}
	r = graph_run(g, status, e);
done:
	if (r < 0 && *status == 0)
		*status = 1;
	graph_free(g);
	return r;
}

int
pipeline_pack(const pipeline_opts *o, const char *dem, int levels,
    vpath_t *vpath, meter *m, int *status, tl_err *e)
{
	graph *g = graph_new(o->prog, o->bindir, e);
	words a = { 0 };
	int r = -1;

	if (g != NULL)
		graph_progress(g, pipeline_progress, m);
	say(&a, "tilepack");
	if (o->force)
		say(&a, "-f");
	if (o->quiet)
		say(&a, "-q");
	if (o->jobs != NULL)
		say(&a, "-j"), say(&a, o->jobs);
	say_demopts(&a, o);
	if (o->name != NULL && strcmp(o->dem, "-") != 0)
		say(&a, "-n"), say(&a, o->name);
	say(&a, dem), say(&a, o->out);
	for (int l = 0; l < levels; l++)
		say(&a, vpath[l]);
	if (g != NULL && graph_exec(g, (char *const *)a.w, -1, -1, e) >= 0)
		r = graph_run(g, status, e);
	else
		*status = 1;
	graph_free(g);
	return r;
}

/* The level of the FQM the chain starts from (--from), 0 from a DEM:
 * its header's (read by the raster layer alone: the supervisor links no
 * georeferencing; the stages check the rest). */
static int
first_level(const pipeline_opts *o, int *first, tl_err *e)
{
	rs_reader *r;
	int x0 = 0, ok;

	*first = 0;
	if (o->from == NULL)
		return 0;
	if ((r = rs_open(o->from, e)) == NULL)
		return -1;
	ok = rs_get_int(rs_header_of(r), FQM_ATTR_LEVEL, first) == 0 &&
	    *first >= 0 && *first < MAXLEVELS;
	(void)rs_get_int(rs_header_of(r), RS_ATTR_X0, &x0);
	rs_close(r);
	if (!ok)
		return tl_fail(e, "%s: no fqm:level", o->from);
	return x0 == 0 ? 0 : tl_fail(e, "%s: a band from column %d, not a "
	    "whole level (give the band list)", o->from, x0);
}

/* -M: the quadric chain only, its vertex maps into the directory o->out,
 * made atomically (an earlier one replaced): a plan's job. A band's
 * directory also gets f.fqm, its columns of level band_levels' FQM. */
int
pipeline_vmaps_only(const pipeline_opts *o, const char *dem, int levels, int w,
    vpath_t *vpath, meter *m, int *status, tl_err *e)
{
	char fpath[PATHMAX];
	tl_outfile d;
	int first, r;

	if (o->band[1] > 0 && (o->band_levels >= levels || o->band[1] > w)) {
		*status = 2;
		return tl_fail(e, "%s: --band %d,%d --band-levels %d: the DEM "
		    "has %d columns and %d levels", o->prog, o->band[0],
		    o->band[1], o->band_levels, w, levels);
	}
	if (o->band[1] > 0)
		levels = o->band_levels;
	if (first_level(o, &first, e) < 0)
		return pipeline_ours(o, e);
	if (first >= levels || tl_outdir_begin(&d, o->out, e) < 0)
		return first >= levels ? tl_fail(e, "%s: %s: level %d, the "
		    "DEM has %d", o->prog, o->from, first, levels) :
		    pipeline_ours(o, e);
	for (int l = first; l < levels; l++)
		snprintf(vpath[l], sizeof vpath[l], "%s/v%d.fqm", d.tmp, l);
	snprintf(fpath, sizeof fpath, "%s/f.fqm", d.tmp);
	tl_progress_start(&m->bar, o->prog, 1000);
	if ((r = pipeline_quadrics(o, dem, first, levels, w, vpath, fpath, m,
	    status, e)) == 0 && (r = tl_outdir_commit(&d, e)) < 0)
		return pipeline_ours(o, e);
	if (r < 0)
		tl_outdir_abort(&d);
	else
		tl_progress_end(&m->bar);
	return r;
}
