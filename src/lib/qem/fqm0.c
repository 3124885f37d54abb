/* fqm0.c - the level-0 FQM from DEM rows (fqm0.h): the DEM read two rows
 * at a time, each row's quadrics made by fqm0_kernel.c's fqm_step0.
 *
 * Level 0 is the fundamental quadric map (FQM) of QEM-filtering (F.
 * Löffler and H. Schumann, "QEM-Filtering: A New Technique For
 * Feature-Sensitive Terrain Mesh Simplification", section 3.2;
 * ../shared/papers/qem-filtering-loeffler-schumann.txt): at every DEM
 * vertex, the Garland-Heckbert quadric of the triangles around it (M.
 * Garland and P. S. Heckbert, "Surface Simplification Using Quadric
 * Error Metrics", SIGGRAPH 1997; quadric.h), the finest level of the
 * VGIS pyramid (P. Lindstrom et al., SIGGRAPH 1996; filter.c). */
#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include "qem/fqm0.h"

int
fqm0_init(fqm0_state *s, dem *d, const geo_ground *m, tl_err *e)
{
	return fqm0_init_cols(s, d, m, 0, dem_georef(d)->width, e);
}

int
fqm0_init_cols(fqm0_state *s, dem *d, const geo_ground *m, int x0, int n,
    tl_err *e)
{
	const georef *g = dem_georef(d);

	memset(s, 0, sizeof *s);
	s->d = d, s->m = m, s->x0 = x0, s->w = n, s->h = g->height;
	assert(s->w >= 3 && s->h >= 3 && x0 >= 0 && x0 + n <= g->width);
	for (int k = 0; k < 2; k++) {
		s->z[k] = tl_alloc(s->w, sizeof *s->z[k], e);
		s->valid[k] = tl_alloc(s->w, 1, e);
		if (s->z[k] == NULL || s->valid[k] == NULL)
			return -1;
	}
	s->part = tl_alloc((size_t)s->w * 6, sizeof *s->part, e);
	return s->part != NULL ? 0 : -1;
}

/* Reads the DEM rows row j needs: j + 1 into the slot of j - 1 (row 0
 * first); row j is then in slot j & 1. Row 0 starts part[] at 0. */
static int
advance(fqm0_state *s, int j, tl_err *e)
{
	assert(j == s->next && j < s->h);
	s->next++;
	if (j == 0) {
		for (size_t k = 0; k < (size_t)s->w * 6; k++)
			s->part[k] = 0;
		if (dem_read_span(s->d, 0, s->x0, s->w, s->z[0], s->valid[0],
		    e) < 0)
			return -1;
	}
	if (j + 1 < s->h && dem_read_span(s->d, j + 1, s->x0, s->w,
	    s->z[!(j & 1)], s->valid[!(j & 1)], e) < 0)
		return -1;
	return 0;
}

int
fqm0_row(fqm0_state *s, int j, fqm_vertex *out, tl_err *e)
{
	int cur = j & 1, more = j + 1 < s->h;

	if (advance(s, j, e) < 0)
		return -1;
	fqm_step0(s->z[cur], s->valid[cur], more ? s->z[!cur] : NULL,
	    more ? s->valid[!cur] : NULL, s->w, j, s->m, s->part, out);
	return 0;
}

void
fqm0_free(fqm0_state *s)
{
	for (int k = 0; k < 2; k++)
		free(s->z[k]), free(s->valid[k]);
	free(s->part);
	memset(s, 0, sizeof *s);
}

int
fqm0_encoded_row(void *ctx, int y, float *row, tl_err *e)
{
	fqm0_source *src = ctx;
	fqm0_state *s = &src->s;
	int cur = y & 1, more = y + 1 < s->h;

	if (advance(s, y, e) < 0)
		return -1;
	fqm_step0_encode(s->z[cur], s->valid[cur], more ? s->z[!cur] : NULL,
	    more ? s->valid[!cur] : NULL, s->w, y, s->m, s->part, &src->L,
	    row);
	return 0;
}
