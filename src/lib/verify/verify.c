/* verify.c - the brute-force pyramid checker (verify.h): the pyramid as a
 * whole (levels, stray files, the DEM), the level checks run
 * (verify_level.c); the violations are noted by verify_note.c. */
#include "verify/verify_impl.h"

#include <assert.h>
#include <dirent.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geo/levels.h"
#include "geo/georef.h"

static const char *const kind_names[VF_NKIND] = {
	"index", "border", "padding", "saturation", "matching", "fold",
	"error", "base", "local", "coverage",
};

const char *
vf_kind_name(int kind)
{
	return kind >= 0 && kind < VF_NKIND ? kind_names[kind] : "?";
}

void
vf_opts_init(vf_opts *o)
{
	memset(o, 0, sizeof *o);
	o->nsweep = 10;
	o->max_issues = 20;
	o->local = 1;
}

/* What the index lists for block k of level l is plausible: a z range,
 * errors finite and >= 0, no base error on level 0. */
static int
entry_ok(const vf_ilevel *L, size_t k, int l)
{
	return L->zmin[k] <= L->zmax[k] && isfinite(L->zmin[k]) &&
	    isfinite(L->zmax[k]) && L->base[k] >= 0 &&
	    isfinite(L->base[k]) && L->emax[k] >= 0 &&
	    L->emax[k] < FLT_MAX && (l != 0 || L->base[k] == 0);
}

/* Levels as vgis(5) says: sizes halving, the top the first of one block
 * (derived here, not taken from the producer's geo_levels). */
static void
check_levels(vf_checker *c)
{
	const vf_index *ix = &c->ix;
	int top = 0;

	while (geo_level_size(ix->size0[0], top) > BT_SIZE ||
	    geo_level_size(ix->size0[1], top) > BT_SIZE)
		top++;
	if (ix->nlevels != top + 1)
		vf_note(c, VF_INDEX, -1, -1, -1, -1, -1, NAN, "%d levels, a "
		    "%dx%d DEM has %d (the top is the first of one block)",
		    ix->nlevels, ix->size0[0], ix->size0[1], top + 1);
	for (int l = 0; l < ix->nlevels; l++) {
		const vf_ilevel *L = &ix->lev[l];
		size_t nb = (size_t)L->blocks[0] * L->blocks[1];
		int w = geo_level_size(ix->size0[0], l);
		int h = geo_level_size(ix->size0[1], l);
		if (L->level != l || L->size[0] != w || L->size[1] != h)
			vf_note(c, VF_INDEX, l, -1, -1, -1, -1, NAN, "index "
			    "entry %d says level %d of %dx%d, level %d is "
			    "%dx%d", l, L->level, L->size[0], L->size[1], l,
			    w, h);
		for (size_t k = 0; k < nb; k++)
			if (!entry_ok(L, k, l))
				vf_note(c, VF_INDEX, l,
				    (int)(k % L->blocks[0]),
				    (int)(k / L->blocks[0]), -1, -1, NAN,
				    "index lists zmin %g zmax %g base %g "
				    "max %g", L->zmin[k], L->zmax[k],
				    L->base[k], L->emax[k]);
	}
}

static void
check_top_strays(vf_checker *c)
{
	struct dirent *de;
	DIR *d;

	if ((d = opendir(c->dir)) == NULL)
		return;
	while ((de = readdir(d)) != NULL) {
		const char *s = de->d_name;
		int l;
		if (strcmp(s, ".") == 0 || strcmp(s, "..") == 0 ||
		    strcmp(s, VGIS_INDEX) == 0)
			continue;
		if (tl_parse_int(s, &l) == 0 && l >= 0 && l < c->ix.nlevels &&
		    s[0] != '+' && (s[0] != '0' || s[1] == '\0'))
			continue;
		vf_note(c, VF_INDEX, -1, -1, -1, -1, -1, NAN, "%s/%s: neither "
		    "index.json nor a level directory", c->dir, s);
	}
	closedir(d);
}

static int
open_dem(vf_checker *c, const char *path, const dem_opts *dopt)
{
	static const dem_opts none;
	const georef *g;
	const char *what;

	if ((c->dem = dem_open(path, dopt ? dopt : &none, c->e)) == NULL)
		return -1;
	g = dem_georef(c->dem);
	c->W = g->width, c->H = g->height;
	if (c->W != c->ix.size0[0] || c->H != c->ix.size0[1])
		return tl_fail(c->e, "%s: %dx%d samples, the pyramid was made "
		    "from %dx%d", path, c->W, c->H, c->ix.size0[0],
		    c->ix.size0[1]);
	if ((what = geo_differs(g, &c->ix.geo)) != NULL)
		vf_note(c, VF_INDEX, -1, -1, -1, -1, -1, NAN, "%s: georef %s "
		    "differs from the index's", path, what);
	c->r->dem = 1;
	return 0;
}

static int
report_init(vf_checker *c)
{
	vf_report *r = c->r;

	r->size0[0] = c->ix.size0[0], r->size0[1] = c->ix.size0[1];
	r->lev = tl_alloc(c->ix.nlevels, sizeof *r->lev, c->e);
	if (r->lev == NULL)
		return -1;
	r->nlevels = c->ix.nlevels;
	for (int l = 0; l < r->nlevels; l++) {
		const vf_ilevel *L = &c->ix.lev[l];
		vf_level *R = &r->lev[l];
		size_t nb = (size_t)L->blocks[0] * L->blocks[1];
		R->level = l;
		R->size[0] = L->size[0], R->size[1] = L->size[1];
		R->blocks[0] = L->blocks[0], R->blocks[1] = L->blocks[1];
		R->displaced = L->displaced;
		for (size_t k = 0; k < nb; k++)
			R->base = fmax(R->base, L->base[k]);
		R->tight = NAN;
	}
	return 0;
}

int
vf_check(const char *dir, const char *dem_path, const dem_opts *dopt,
    const vf_opts *o, vf_report *r, tl_err *e)
{
	vf_checker c;
	int ret = -1, disp = 0;

	memset(&c, 0, sizeof c);
	memset(r, 0, sizeof *r);
	c.dir = dir, c.r = r, c.e = e;
	if (o != NULL)
		c.o = *o;
	else
		vf_opts_init(&c.o);
	if (c.o.max_issues < 0)
		c.o.max_issues = 0;
	if (vf_tree_init(&c.tree, e) < 0)
		return -1;
	if (vf_index_read(dir, &c.ix, e) < 0)
		goto done;
	if (report_init(&c) < 0)
		goto done;
	c.W = c.ix.size0[0], c.H = c.ix.size0[1];
	if (dem_path != NULL && open_dem(&c, dem_path, dopt) < 0)
		goto done;
	for (int l = 0; l < c.ix.nlevels; l++)
		disp |= c.ix.lev[l].displaced;
	if (disp && geo_ground_init(&c.metric, &c.ix.geo, e) < 0)
		goto done;
	check_levels(&c);
	check_top_strays(&c);
	for (int l = 0; l < c.ix.nlevels; l++)
		if (vf_level_check(&c, l) < 0)
			goto done;
	ret = 0;
done:
	if (c.dem != NULL)
		dem_close(c.dem);
	geo_ground_free(&c.metric);
	vf_index_free(&c.ix);
	vf_tree_free(&c.tree);
	return ret;
}

void
vf_report_free(vf_report *r)
{
	for (int l = 0; l < r->nlevels && r->lev; l++)
		free(r->lev[l].tau);
	free(r->lev);
	free(r->issue);
	memset(r, 0, sizeof *r);
}
