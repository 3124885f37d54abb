/* fqm_input.h - an FQM read row by row, as the filters read their input
 * (fqmfilter, fqmsolve): opened with its info, layout and metric; every
 * row checked for NaN and infinities (fqm_check_row), then decoded. */
#ifndef TL_FQM_INPUT_H
#define TL_FQM_INPUT_H

#include "qem/fqm.h"

typedef struct {
	rs_reader *r;
	const rs_header *h;
	const char *what; /* the input, for messages */
	fqm_info fi;
	fqm_layout L;
	geo_ground m;
	float *buf;       /* a row, for a reader that copies */
	const float *row; /* the row read last: buf, or where the reader
	                   * holds it until the next read (rs_read_row_view) */
	fqm_vertex *v;    /* the row read last, decoded (h->width) */
	int y;            /* rows read */
} fqm_input;

/* path: an EXR file or "-" (the stream on stdin). */
int fqm_input_open(fqm_input *in, const char *path, tl_err *e);
/* Reads, checks and decodes the next row into in->v. */
int fqm_input_next(fqm_input *in, tl_err *e);
/* Reads and checks the next row into in->row, without decoding it. */
int fqm_input_read(fqm_input *in, tl_err *e);
void fqm_input_close(fqm_input *in);

#endif
