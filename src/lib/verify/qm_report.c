/* qm_report.c - tilecheck --terrain's report: the kinds of violation,
 * and each one counted and the first of each kind kept. A leaf: every
 * check (qm_tile.c, qm_layer.c, qm_seam.c, qm_dem.c) adds to it, and
 * qm_run.c, which runs them, prints it. */
#include "verify/qm.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *kind_names[QM_NKIND] = {
	"decode", "header", "heights", "sphere", "occlusion", "index",
	"winding", "degenerate", "hole", "edges", "extension", "layer",
	"unannounced", "missing", "ancestor", "seam", "coverage", "error",
};

const char *
qm_kind_name(int kind)
{
	return kind >= 0 && kind < QM_NKIND ? kind_names[kind] : "?";
}

void
qm_report_init(qm_report *r)
{
	memset(r, 0, sizeof *r);
	r->maxz = -1;
	r->max_issues = 20;
	r->level_error = qm_level_error;
}

void
qm_report_free(qm_report *r)
{
	for (int z = 0; z <= QM_MAXZ; z++)
		free(r->lev[z].ratio);
	free(r->issue);
	memset(r, 0, sizeof *r);
}

void
qm_issue_add(qm_report *r, int kind, int z, int x, int y, const char *fmt,
    ...)
{
	qm_issue *i;
	va_list ap;

	r->count[kind]++, r->total++;
	if (r->kept[kind] >= r->max_issues)
		return;
	if (r->nissue == r->capissue) {
		int cap = r->capissue ? 2 * r->capissue : 64;
		qm_issue *p = realloc(r->issue, (size_t)cap * sizeof *p);

		if (p == NULL)
			return;
		r->issue = p, r->capissue = cap;
	}
	i = &r->issue[r->nissue++];
	r->kept[kind]++;
	i->kind = kind, i->z = z, i->x = x, i->y = y;
	va_start(ap, fmt);
	vsnprintf(i->text, sizeof i->text, fmt, ap);
	va_end(ap);
}
