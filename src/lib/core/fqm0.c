/* fqm0.c - the level-0 FQM from DEM rows (fqm0.h). */
#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include "core/fqm0.h"

int
fqm0_init(fqm0_state *s, dem *d, const geo_metric *m, tl_err *e)
{
	const georef *g = dem_georef(d);

	memset(s, 0, sizeof *s);
	s->d = d, s->m = m, s->w = g->width, s->h = g->height;
	assert(s->w >= 3 && s->h >= 3);
	for (int k = 0; k < 2; k++) {
		s->z[k] = tl_alloc(s->w, sizeof *s->z[k], e);
		s->valid[k] = tl_alloc(s->w, 1, e);
		s->band[k] = tl_alloc((size_t)(s->w - 1) * FQM_BAND0_DOUBLES,
		    sizeof(double), e);
		if (s->z[k] == NULL || s->valid[k] == NULL ||
		    s->band[k] == NULL)
			return -1;
	}
	return 0;
}

int
fqm0_row(fqm0_state *s, int j, fqm_vertex *out, tl_err *e)
{
	int cur = j & 1, nxt = !cur;

	assert(j == s->next && j < s->h);
	s->next++;
	if (j == 0 && dem_read_row(s->d, 0, s->z[0], s->valid[0], e) < 0)
		return -1;
	/* band j (rows j, j+1) goes where band j-2 was */
	if (j + 1 < s->h) {
		if (dem_read_row(s->d, j + 1, s->z[nxt], s->valid[nxt], e) < 0)
			return -1;
		fqm_band0(s->z[cur], s->valid[cur], s->z[nxt], s->valid[nxt],
		    s->w, j, s->m, s->band[cur]);
	}
	fqm_row0(j > 0 ? s->band[nxt] : NULL,
	    j + 1 < s->h ? s->band[cur] : NULL, s->z[cur], s->valid[cur],
	    s->w, out);
	return 0;
}

void
fqm0_free(fqm0_state *s)
{
	for (int k = 0; k < 2; k++)
		free(s->z[k]), free(s->valid[k]), free(s->band[k]);
	memset(s, 0, sizeof *s);
}

int
fqm0_encoded_row(void *ctx, int y, float *row, tl_err *e)
{
	fqm0_source *src = ctx;

	if (fqm0_row(&src->s, y, src->fv, e) < 0)
		return -1;
	fqm_encode(&src->L, src->fv, src->s.w, row);
	return 0;
}
