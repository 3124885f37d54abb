/* verify_note.c - a violation noted (verify_impl.h): counted, and the
 * first o.max_issues of each kind and level kept with their text. The
 * leaf every check writes through. */
#include "verify/verify_impl.h"

#include <assert.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

void
vf_note(vf_checker *c, int kind, int level, int bi, int bj, int gi, int gj,
    double tau, const char *fmt, ...)
{
	vf_report *r = c->r;
	int *kept = level >= 0 ? r->lev[level].kept : r->kept;
	vf_issue *s;
	va_list ap;

	assert(kind >= 0 && kind < VF_NKIND && level < r->nlevels);
	r->count[kind]++;
	r->total++;
	if (level >= 0)
		r->lev[level].count[kind]++;
	if (kept[kind] >= c->o.max_issues)
		return;
	if (r->nissue == r->capissue) {
		int cap = r->capissue ? 2 * r->capissue : 64;
		vf_issue *p = realloc(r->issue, (size_t)cap * sizeof *p);
		if (p == NULL)
			return; /* counted, not kept */
		r->issue = p, r->capissue = cap;
	}
	kept[kind]++;
	s = &r->issue[r->nissue++];
	s->kind = kind, s->level = level;
	s->block[0] = bi, s->block[1] = bj;
	s->vertex[0] = gi, s->vertex[1] = gj;
	s->tau = tau;
	va_start(ap, fmt);
	vsnprintf(s->text, sizeof s->text, fmt, ap);
	va_end(ap);
}
