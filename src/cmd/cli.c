/* cli.c - the programs' shared start-up: name, help, version, shared
 * options, operands, exit statuses (cli.h). */
#include <assert.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

static const struct option shared_long[] = {
	{ "help", no_argument, NULL, 'h' },
	{ "version", no_argument, NULL, 'V' },
	{ "resample", no_argument, NULL, DEM_RESAMPLE }, /* CLI_DEM only */
};

/* The program's name for the check of stdout at exit, and whether a
 * failure was already reported (its status is 1 already). */
static const char *exit_prog;
static int exit_failed;

/* What went to stdout (a report, a listing, --help) must have arrived: a
 * write that failed (a full disk, /dev/full, EIO), now or earlier in a
 * flush, turns the exit into a failure with the reason, as gnulib's
 * close_stdout does. Runs at exit. */
static void
check_stdout(void)
{
	int err = 0;

	if (fflush(stdout) != 0)
		err = errno;
	else if (ferror(stdout))
		err = -1;
	if (fclose(stdout) != 0 && err == 0 && errno != EBADF)
		err = errno;
	if (err == 0 || exit_failed)
		return;
	if (err < 0)
		fprintf(stderr, "%s: stdout: write error\n", exit_prog);
	else
		fprintf(stderr, "%s: stdout: %s\n", exit_prog, strerror(err));
	_exit(CLI_FAIL);
}

void
cli_init(cli *c, char **argv, const char *usage, int sets)
{
	const char *slash = strrchr(argv[0], '/');
	static int once;

	memset(c, 0, sizeof *c);
	c->prog = slash != NULL && slash[1] != '\0' ? slash + 1 : argv[0];
	argv[0] = (char *)c->prog; /* getopt prints argv[0] */
	c->usage = usage;
	c->sets = sets;
	c->comp = RS_ZIP;
	c->status = -1;
	exit_prog = c->prog;
	if (once++ == 0)
		atexit(check_stdout);
	/* over the file size limit (ulimit -f) a write fails with EFBIG
	 * instead of killing the process: the failure path removes the
	 * temporaries and says why */
	signal(SIGXFSZ, SIG_IGN);
}

/* The program's options and the shared ones, in one optstring and one
 * long option table (built once). */
static void
build(cli *c, const char *optstring, const struct option *longopts)
{
	size_t n = 0;

	snprintf(c->optstring, sizeof c->optstring, "%shV%s%s",
	    optstring != NULL ? optstring : "",
	    c->sets & CLI_COMPRESSION ? "z:" : "",
	    c->sets & CLI_DEM ? DEM_OPTS : "");
	for (; longopts != NULL && longopts[n].name != NULL; n++) {
		assert(n + 4 < CLI_MAXLONG);
		c->longopts[n] = longopts[n];
	}
	c->longopts[n++] = shared_long[0];
	c->longopts[n++] = shared_long[1];
	if (c->sets & CLI_DEM)
		c->longopts[n++] = shared_long[2];
	memset(&c->longopts[n], 0, sizeof c->longopts[n]);
}

/* A shared option: 1 handled (c->status set when the program must
 * exit), 0 not a shared one. */
static int
shared(cli *c, int ch, const char *arg)
{
	tl_err e;

	switch (ch) {
	case 'h':
		cli_usage(c, stdout);
		c->status = CLI_OK;
		return 1;
	case 'V':
		printf("%s %s\n", c->prog, TL_VERSION);
		c->status = CLI_OK;
		return 1;
	case 'z':
		if (!(c->sets & CLI_COMPRESSION))
			return 0;
		if (rs_compression_parse(arg, &c->comp) < 0)
			c->status = cli_bad(c, "-z %s: unknown compression", arg);
		return 1;
	}
	if (!(c->sets & CLI_DEM))
		return 0;
	switch (dem_option(&c->dem, ch, arg, &e)) {
	case 1:
		return 1;
	case -1:
		c->status = cli_bad(c, "%s", e.msg);
		return 1;
	}
	return 0;
}

int
cli_next(cli *c, int argc, char **argv, const char *optstring,
    const struct option *longopts)
{
	int ch;

	if (c->status >= 0) /* a bad value of the last option */
		return -1;
	if (c->optstring[0] == '\0')
		build(c, optstring, longopts);
	while ((ch = getopt_long(argc, argv, c->optstring, c->longopts,
	    NULL)) != -1) {
		if (ch == '?' || ch == ':') { /* getopt has said why */
			c->status = cli_usage_error(c);
			return -1;
		}
		if (!shared(c, ch, optarg))
			return ch;
		if (c->status >= 0)
			return -1;
	}
	return -1;
}

void
cli_usage(const cli *c, FILE *f)
{
	fprintf(f, "usage: %s %s", c->prog, c->usage);
}

int
cli_usage_error(const cli *c)
{
	cli_usage(c, stderr);
	return CLI_USAGE;
}

static void
vwarn(const cli *c, const char *fmt, va_list ap)
{
	fprintf(stderr, "%s: ", c->prog);
	vfprintf(stderr, fmt, ap);
	fputc('\n', stderr);
}

int
cli_bad(const cli *c, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	vwarn(c, fmt, ap);
	va_end(ap);
	return CLI_USAGE;
}

void
cli_warn(const cli *c, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	vwarn(c, fmt, ap);
	va_end(ap);
}

int
cli_operands(const cli *c, int argc, char **argv, const char **in,
    const char **out)
{
	int r = tl_operands(c->prog, argc, argv, in, out);

	return r == CLI_USAGE ? cli_usage_error(c) : r;
}

int
cli_filter_args(const cli *c, int argc, char **argv, const char **in,
    const char **out)
{
	int r;

	if (c->status >= 0)
		return c->status;
	r = cli_operands(c, argc - optind, argv + optind, in, out);
	return r != 0 ? r : -1;
}

int
cli_exit(const cli *c, int r, const tl_err *e)
{
	static const int limits[] = { EMFILE, EFBIG };
	const char *hint = "";

	if (r >= 0)
		return CLI_OK;
	/* the reason from a library's own words (OpenEXR, dlopen) says
	 * which limit to raise too */
	for (int k = 0; k < 2; k++)
		if (strstr(e->msg, strerror(limits[k])) != NULL &&
		    strstr(e->msg, tl_errno_hint(limits[k])) == NULL)
			hint = tl_errno_hint(limits[k]);
	cli_warn(c, "%s%s", e->msg, hint);
	exit_failed = 1; /* a write to stdout that failed has been told */
	return CLI_FAIL;
}

int
cli_columns(const char *s, int r[2])
{
	char *end;
	long a, b;

	errno = 0;
	a = strtol(s, &end, 10);
	if (end == s || *end != ',')
		return -1;
	s = end + 1;
	b = strtol(s, &end, 10);
	if (end == s || *end != '\0' || errno != 0 || a < 0 || b <= a ||
	    b > INT_MAX)
		return -1;
	r[0] = (int)a, r[1] = (int)b;
	return 0;
}

long long
cli_number(cli *c, const char *opt, const char *s, long long lo,
    long long hi)
{
	long long v;

	if (tl_parse_ll(s, &v) < 0)
		c->status = cli_bad(c, "%s: not an integer: \"%s\"", opt, s);
	else if (v < lo || v > hi)
		c->status = cli_bad(c, "%s: %lld is out of range (%lld .. %lld)",
		    opt, v, lo, hi);
	else
		return v;
	return lo;
}

double
cli_real(cli *c, const char *opt, const char *s, double lo, double hi)
{
	double v;

	if (tl_parse_double(s, &v) < 0 || !isfinite(v))
		c->status = cli_bad(c, "%s: not a number: \"%s\"", opt, s);
	else if (v < lo || v > hi)
		c->status = cli_bad(c, "%s: %g is out of range (%g .. %g)", opt,
		    v, lo, hi);
	else
		return v;
	return lo;
}

int
cli_jobs(void)
{
	long n = sysconf(_SC_NPROCESSORS_ONLN);

	return n < 1 ? 1 : n > CLI_JOBS_MAX ? CLI_JOBS_MAX : (int)n;
}
