/* t3c_run.c - tilecheck --terrain on the 3D Tiles terrain profile: the
 * tileset read (t3c_set.c), every glb decoded and checked, the seams,
 * the DEM measured through qm_dem_measure with this profile's reader and
 * E_L, the report as qm_run prints it (issues named by their glb), or
 * the dump. */
#include "verify/t3c.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The kinds as this profile words them: metadata for the header,
 * tileset for layer.json. */
static const char *const names[QM_NKIND] = {
	"decode", "metadata", "heights", "sphere", "occlusion", "index",
	"winding", "degenerate", "hole", "edges", "extension", "tileset",
	"unannounced", "missing", "ancestor", "seam", "coverage", "error",
};

typedef struct {
	const char *dir;
	const t3c_set *T;
} run;

static void
tile_name(const void *ctx, int z, int x, int y, char *b, size_t n)
{
	t3c_path(NULL, ctx, z, x, y, b, n);
}

/* The tile quantised back as quantized-mesh has it (u, v to steps,
 * heights to steps of the metadata's range): qm_checksum's. */
static uint32_t
checksum(const t3c_tile *t, const t3c_meta *m, const double *uv,
    const double *h)
{
	qm_tile q;
	uint32_t c = 0;
	double span = m != NULL ? m->hmax - m->hmin : 0;

	memset(&q, 0, sizeof q);
	q.n = t->n, q.ntri = t->ntri;
	q.u = malloc(((size_t)t->n + 1) * sizeof *q.u);
	q.v = malloc(((size_t)t->n + 1) * sizeof *q.v);
	q.h = malloc(((size_t)t->n + 1) * sizeof *q.h);
	q.idx = malloc((3 * (size_t)t->ntri + 1) * sizeof *q.idx);
	if (q.u != NULL && q.v != NULL && q.h != NULL && q.idx != NULL) {
		for (uint32_t i = 0; i < t->n; i++) {
			q.u[i] = (int32_t)lround(uv[2 * i]);
			q.v[i] = (int32_t)lround(uv[2 * i + 1]);
			q.h[i] = span > 0 ? (int32_t)lround((h[i] - m->hmin) /
			    span * QM_MAXQ) : 0;
		}
		for (size_t k = 0; k < 3 * (size_t)t->ntri; k++)
			q.idx[k] = t->idx[k];
		c = qm_checksum(&q);
	}
	qm_free(&q);
	return c;
}

static void
dump_line(const t3c_tile *t, const t3c_meta *m, int z, int x, int y)
{
	double *uv = malloc((2 * (size_t)t->n + 1) * sizeof *uv);
	double *h = malloc(((size_t)t->n + 1) * sizeof *h);
	unsigned char *pole = malloc((size_t)t->n + 1);

	if (uv != NULL && h != NULL && pole != NULL) {
		t3c_place(t, z, x, y, uv, h, pole);
		printf("%d/%d/%d vertices %u triangles %u checksum %08x\n", z,
		    x, y, t->n, t->ntri, checksum(t, m, uv, h));
	}
	free(uv), free(h), free(pole);
}

/* Every glb present read, checked and counted; with dump, its line. */
static void
tiles(const char *dir, const t3c_set *T, int dump, qm_report *r)
{
	char path[4096];
	const qm_set *s = &T->s;

	for (long i = 0; i < s->n; i++) {
		int z = QM_KZ(s->key[i]), x = QM_KX(s->key[i]);
		int y = QM_KY(s->key[i]);
		const t3c_meta *m = t3c_set_meta(T, s->key[i]);
		qm_level *L = &r->lev[z];
		t3c_tile t;
		tl_err e;

		t3c_path(dir, T, z, x, y, path, sizeof path);
		if (z > r->maxz)
			r->maxz = z;
		L->tiles++;
		if (t3c_read(path, &t, &e) < 0) {
			qm_issue_add(r, QM_DECODE, z, x, y, "%s", e.msg);
			t3c_free(&t);
			continue;
		}
		L->vertices += t.n, L->triangles += t.ntri;
		if (dump)
			dump_line(&t, m, z, x, y);
		else if (m != NULL)
			t3c_tile_check(&t, m, z, x, y, r);
		t3c_free(&t);
	}
}

/* The DEM's reader: the glb placed; 1 when it does not decode or a
 * vertex lies outside its rectangle (reported by the tile's checks). */
static int
load(void *ctx, qm_key k, qm_mesh *M)
{
	const run *R = ctx;
	char path[4096];
	t3c_tile t;
	double *h = NULL;
	tl_err e;
	int st = 1;

	memset(M, 0, sizeof *M);
	t3c_path(R->dir, R->T, QM_KZ(k), QM_KX(k), QM_KY(k), path,
	    sizeof path);
	if (t3c_read(path, &t, &e) < 0)
		goto done;
	st = -1;
	M->p = malloc((3 * (size_t)t.n + 1) * sizeof *M->p);
	M->uv = malloc((2 * (size_t)t.n + 1) * sizeof *M->uv);
	M->pole = malloc((size_t)t.n + 1);
	M->tri = malloc((3 * (size_t)t.ntri + 1) * sizeof *M->tri);
	h = malloc(((size_t)t.n + 1) * sizeof *h);
	if (M->p == NULL || M->uv == NULL || M->pole == NULL ||
	    M->tri == NULL || h == NULL)
		goto done;
	M->n = t.n;
	memcpy(M->p, t.p, 3 * (size_t)t.n * sizeof *t.p);
	t3c_place(&t, QM_KZ(k), QM_KX(k), QM_KY(k), M->uv, h, M->pole);
	st = 1;
	for (size_t i = 0; i < 2 * (size_t)t.n; i++)
		if (M->uv[i] < 0 || M->uv[i] > QM_MAXQ)
			goto done;
	for (uint32_t j = 0; j < t.ntri; j++) {
		const uint32_t *c = t.idx + 3 * (size_t)j;

		if (c[0] >= t.n || c[1] >= t.n || c[2] >= t.n)
			continue;
		memcpy(M->tri + 3 * (size_t)M->ntri++, c, 3 * sizeof *c);
	}
	st = 0;
done:
	if (st != 0)
		qm_mesh_free(M);
	t3c_free(&t);
	free(h);
	return st;
}

static void
report_init(qm_report *r, const t3c_set *T)
{
	qm_report_init(r);
	r->level_error = t3c_level_error;
	r->names = names;
	r->tile_name = tile_name, r->name_ctx = T;
}

int
t3c_run(const qm_args *a, const char *prog)
{
	qm_report r;
	t3c_set T;
	tl_err e;
	run R = { a->dir, &T };
	int st = -1;

	report_init(&r, &T);
	if (t3c_set_read(a->dir, &T, &r, &e) < 0)
		goto fail;
	if (a->dump) {
		tiles(a->dir, &T, 1, &r);
		st = r.count[QM_DECODE] > 0;
		for (int i = 0; i < r.nissue; i++)
			if (r.issue[i].kind == QM_DECODE && r.issue[i].z >= 0)
				fprintf(stderr, "%s: %d/%d/%d: %s\n", prog,
				    r.issue[i].z, r.issue[i].x, r.issue[i].y,
				    r.issue[i].text);
		goto done;
	}
	tiles(a->dir, &T, 0, &r);
	t3c_seam_check(a->dir, &T, &r);
	if (a->dem_path != NULL) {
		r.dem = 1;
		if (qm_dem_measure(&T.s, load, &R, a->dem_path, &a->dem, &r,
		    &e) < 0)
			goto fail;
	}
	qm_report_print(stdout, &r, &T.s, a->dir, a->dem_path);
	st = r.total > 0;
	goto done;
fail:
	fprintf(stderr, "%s: %s\n", prog, e.msg);
done:
	t3c_set_free(&T);
	qm_report_free(&r);
	return st;
}
