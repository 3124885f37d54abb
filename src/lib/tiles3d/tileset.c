/* tileset.c - tileset.json: an explicit quadtree on the pyramid's levels,
 * the top block the root, each block the parent of the up to four blocks
 * of the level below that it covers (t3_impl.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "base/json.h"
#include "tiles3d/t3_impl.h"

/* Children are drawn where their parent's error is too coarse: a parent
 * whose bound is below a child's takes the child's, still a true bound
 * of its own mesh, so that errors never grow down the tree. */
static double
settle(const t3_set *s, t3_tile *t, int *raised)
{
	double m = 0;

	if (t->level == 0)
		return t->error;
	for (int dj = 0; dj < 2; dj++)
		for (int di = 0; di < 2; di++) {
			int ci = 2 * t->bi + di, cj = 2 * t->bj + dj;
			const pyramid_level *L = &s->ix->lev[t->level - 1];
			if (ci < L->blocks[0] && cj < L->blocks[1])
				m = fmax(m, settle(s, t3_at(s, t->level - 1,
				    ci, cj), raised));
		}
	if (m > t->error)
		t->error = m, (*raised)++;
	return t->error;
}

static json_t *
numbers(const double *v, int n)
{
	json_t *a = json_array();

	for (int k = 0; k < n; k++)
		json_array_append_new(a, json_real(v[k]));
	return a;
}

/* The tile's frame relative to its parent's (3D Tiles composes them),
 * column-major: p -> parent^-1 (c + R^T p). */
static json_t *
transform(const t3_frame *f, const t3_frame *up)
{
	double m[16] = { 0 }, d[3];

	for (int a = 0; a < 3; a++)
		d[a] = f->c[a] - (up ? up->c[a] : 0);
	for (int j = 0; j < 3; j++) /* column j: row j of R, in the parent */
		for (int a = 0; a < 3; a++)
			m[4 * j + a] = up ? up->r[3 * a] * f->r[3 * j] +
			    up->r[3 * a + 1] * f->r[3 * j + 1] +
			    up->r[3 * a + 2] * f->r[3 * j + 2] :
			    f->r[3 * j + a];
	for (int a = 0; a < 3; a++)
		m[12 + a] = up ? up->r[3 * a] * d[0] + up->r[3 * a + 1] * d[1] +
		    up->r[3 * a + 2] * d[2] : d[a];
	m[15] = 1;
	return numbers(m, 16);
}

static json_t *
tile_json(const t3_set *s, geo_proj *p, const t3_tile *t, const t3_tile *up,
    tl_err *e)
{
	char uri[64];
	double v[12];
	json_t *j, *kids;

	if (t3_volume(s, p, t, v, e) < 0)
		return NULL;
	snprintf(uri, sizeof uri, "%d/%d_%d.glb", t->level, t->bj, t->bi);
	j = json_pack("{s:{s:o}, s:f, s:{s:s}, s:o}", "boundingVolume",
	    s->region ? "region" : "box", numbers(v, s->region ? 6 : 12),
	    "geometricError", t->error, "content", "uri", uri, "transform",
	    transform(&t->f, up ? &up->f : NULL));
	if (up == NULL)
		json_object_set_new(j, "refine", json_string("REPLACE"));
	if (t->level == 0)
		return j;
	kids = json_array();
	json_object_set_new(j, "children", kids);
	for (int dj = 0; dj < 2; dj++)
		for (int di = 0; di < 2; di++) {
			const pyramid_level *L = &s->ix->lev[t->level - 1];
			int ci = 2 * t->bi + di, cj = 2 * t->bj + dj;
			json_t *c;
			if (ci >= L->blocks[0] || cj >= L->blocks[1])
				continue;
			c = tile_json(s, p, t3_at(s, t->level - 1, ci, cj), t, e);
			if (c == NULL) {
				json_decref(j);
				return NULL;
			}
			json_array_append_new(kids, c);
		}
	return j;
}

int
t3_tileset_write(const t3_set *s, geo_proj *p, const char *dir, int *raised,
    tl_err *e)
{
	t3_tile *root = t3_at(s, s->ix->nlevels - 1, 0, 0);
	char path[4096];
	json_t *j, *r;
	double relief;

	*raised = 0;
	settle(s, root, raised);
	if ((r = tile_json(s, p, root, NULL, e)) == NULL)
		return -1;
	/* drawing nothing misses the whole relief, at least the root's error */
	relief = s->zhi[root - s->tile] - s->zlo[root - s->tile];
	j = json_pack("{s:{s:s}, s:f, s:o}", "asset", "version", "1.1",
	    "geometricError", fmax(root->error, relief), "root", r);
	snprintf(path, sizeof path, "%s/tileset.json", dir);
	if (j == NULL || json_dump_file(j, path, JSON_INDENT(1) |
	    JSON_SORT_KEYS | JSON_REAL_PRECISION(17)) != 0) {
		json_decref(j);
		return tl_fail(e, "%s: cannot write it", path);
	}
	json_decref(j);
	return 0;
}
