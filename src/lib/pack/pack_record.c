/* pack_record.c - a job's text record (a piece's in pack_jobs.c, a
 * part's in pack_parts.c), written last and atomically (pack_impl.h):
 * the leaf both write through. */
#include "pack/pack_impl.h"

#include <stdio.h>
#include <unistd.h>

#include "base/outfile.h"

FILE *
pk_record_open(tl_outfile *o, const char *path, tl_err *e)
{
	FILE *f;

	if (tl_out_begin(o, path, e) < 0)
		return NULL;
	if ((f = fdopen(dup(o->fd), "w")) == NULL) {
		tl_out_abort(o);
		tl_failsys(e, "%s", path);
	}
	return f;
}

int
pk_record_close(tl_outfile *o, FILE *f, tl_err *e)
{
	if (fclose(f) != 0) {
		tl_out_abort(o);
		return tl_failsys(e, "%s", o->path);
	}
	return tl_out_commit(o, e);
}
