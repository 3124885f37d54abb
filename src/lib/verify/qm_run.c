/* qm_run.c - tilecheck --terrain: the tileset read and every tile
 * checked, the report (per level and the violations kept) or the dump
 * (per tile its counts and checksum, what tests/js/qmdecode.js prints
 * from a third-party decoder). */
#include "verify/qm.h"

#include <stdlib.h>
#include <string.h>

static int
cmpd(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;

	return x < y ? -1 : x > y;
}

static void
print_level(FILE *f, const qm_report *r, int z)
{
	const qm_level *L = &r->lev[z];

	fprintf(f, "level %d: %lld tiles (%lld gzip'd), %lld vertices, "
	    "%lld triangles\n", z, L->tiles, L->gzip, L->vertices,
	    L->triangles);
	if (!r->dem)
		return;
	fprintf(f, "  E_L %.6g m, %lld valid samples", r->level_error(z),
	    L->samples);
	if (L->nratio > 0) {
		double *s = malloc((size_t)L->nratio * sizeof *s), med;

		if (s == NULL)
			return;
		memcpy(s, L->ratio, (size_t)L->nratio * sizeof *s);
		qsort(s, (size_t)L->nratio, sizeof *s, cmpd);
		med = L->nratio % 2 ? s[L->nratio / 2] :
		    0.5 * (s[L->nratio / 2 - 1] + s[L->nratio / 2]);
		fprintf(f, ", error / E_L over %ld tiles: max %.4f median "
		    "%.4f (largest %.4g m in %d/%d/%d)", L->nratio,
		    s[L->nratio - 1], med, L->worst, z, L->worst_tile[0],
		    L->worst_tile[1]);
		free(s);
	}
	fputc('\n', f);
}

static const char *
kind(const qm_report *r, int k)
{
	return r->names != NULL ? r->names[k] : qm_kind_name(k);
}

void
qm_report_print(FILE *f, const qm_report *r, const qm_set *s,
    const char *dir, const char *dem_path)
{
	char name[256];

	fprintf(f, "terrain %s: %ld tiles, %ld announced, levels 0..%d%s%s\n",
	    dir, s->n, s->navail, r->maxz, dem_path ? ", against " : "",
	    dem_path ? dem_path : "");
	for (int z = 0; z <= r->maxz; z++)
		print_level(f, r, z);
	fprintf(f, "violations:");
	for (int k = 0; k < QM_NKIND; k++)
		if (r->dem || (k != QM_COVERAGE && k != QM_ERROR))
			fprintf(f, " %s %lld", kind(r, k), r->count[k]);
		else
			fprintf(f, " %s -", kind(r, k));
	fputc('\n', f);
	for (int i = 0; i < r->nissue; i++) {
		const qm_issue *q = &r->issue[i];

		if (q->z < 0)
			fprintf(f, "tileset: %s: %s\n", kind(r, q->kind),
			    q->text);
		else if (r->tile_name != NULL) {
			r->tile_name(r->name_ctx, q->z, q->x, q->y, name,
			    sizeof name);
			fprintf(f, "%s: %s: %s\n", name, kind(r, q->kind),
			    q->text);
		} else
			fprintf(f, "%d/%d/%d: %s: %s\n", q->z, q->x, q->y,
			    kind(r, q->kind), q->text);
	}
	if (r->total == 0) {
		fprintf(f, "result: pass\n");
		return;
	}
	fprintf(f, "result: FAIL, %lld violations:", r->total);
	for (int k = 0; k < QM_NKIND; k++)
		if (r->count[k])
			fprintf(f, " %s %lld", kind(r, k), r->count[k]);
	fputc('\n', f);
}

/* Every tile present read, checked and counted; with dump, its line. */
static void
tiles(const char *dir, const qm_set *s, int dump, qm_report *r)
{
	char path[4096];

	for (long i = 0; i < s->n; i++) {
		int z = QM_KZ(s->key[i]), x = QM_KX(s->key[i]);
		int y = QM_KY(s->key[i]);
		qm_level *L = &r->lev[z];
		qm_tile t;
		tl_err e;

		snprintf(path, sizeof path, "%s/%d/%d/%d.terrain", dir, z, x,
		    y);
		if (z > r->maxz)
			r->maxz = z;
		L->tiles++;
		if (qm_read(path, &t, &e) < 0) {
			qm_issue_add(r, QM_DECODE, z, x, y, "%s", e.msg);
			qm_free(&t);
			continue;
		}
		L->gzip += t.gzip;
		L->vertices += t.n, L->triangles += t.ntri;
		if (dump)
			printf("%d/%d/%d vertices %u triangles %u checksum "
			    "%08x\n", z, x, y, t.n, t.ntri, qm_checksum(&t));
		else {
			qm_tile_check(&t, z, x, y, s->normals, r);
			qm_metadata_check(s, &t, z, x, y, r);
		}
		qm_free(&t);
	}
}

int
qm_check(const char *dir, const char *dem_path, const dem_opts *o,
    qm_set *s, qm_report *r, tl_err *e)
{
	qm_report_init(r);
	if (qm_set_read(dir, s, r, e) < 0)
		return -1;
	tiles(dir, s, 0, r);
	qm_seam_check(dir, s, r);
	if (dem_path == NULL)
		return 0;
	r->dem = 1;
	return qm_dem_check(dir, s, dem_path, o, r, e);
}

static int
dump(const qm_args *a, const char *prog)
{
	qm_report r;
	qm_set s;
	tl_err e;
	int st;

	qm_report_init(&r);
	if (qm_set_read(a->dir, &s, &r, &e) < 0) {
		fprintf(stderr, "%s: %s\n", prog, e.msg);
		qm_report_free(&r);
		return -1;
	}
	tiles(a->dir, &s, 1, &r);
	st = r.count[QM_DECODE] > 0;
	for (int i = 0; i < r.nissue; i++)
		if (r.issue[i].kind == QM_DECODE)
			fprintf(stderr, "%s: %d/%d/%d: %s\n", prog,
			    r.issue[i].z, r.issue[i].x, r.issue[i].y,
			    r.issue[i].text);
	qm_set_free(&s);
	qm_report_free(&r);
	return st;
}

int
qm_run(const qm_args *a, const char *prog)
{
	qm_report r;
	qm_set s;
	tl_err e;
	int st;

	if (a->dump)
		return dump(a, prog);
	if (qm_check(a->dir, a->dem_path, &a->dem, &s, &r, &e) < 0) {
		fprintf(stderr, "%s: %s\n", prog, e.msg);
		st = -1;
	} else {
		qm_report_print(stdout, &r, &s, a->dir, a->dem_path);
		st = r.total > 0;
	}
	qm_set_free(&s);
	qm_report_free(&r);
	return st;
}
