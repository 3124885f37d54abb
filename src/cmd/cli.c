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
#include "base/outfile.h"

static const struct option shared_long[] = {
	{ "help", no_argument, NULL, 'h' },
	{ "version", no_argument, NULL, 'V' },
};

/* The DEM options (dem.h's dem_option applies them): the one table that
 * the parser (build), the usage (cli_usage) and the argv words passed on
 * to a stage (cli_dem_argv) read. */
static const struct {
	int ch;            /* the letter, or DEM_RESAMPLE for a long one */
	const char *flag;  /* as a stage is given it */
	const char *arg;   /* its argument's name, NULL: none */
	const char *help;  /* '\n' continues the help on the next line */
} dem_flags[] = {
	{ 'D', "-D", "datum", "the DEM's vertical datum (EPSG:5773) when it "
	    "declares none" },
	{ 'e', "-e", "encoding", "auto (default), grey, terrainrgb, terrarium" },
	{ 'H', "-H", "datum", "convert heights to datum: ellipsoid (WGS 84) or "
	    "EPSG:n" },
	{ 'N', "-N", "nodata", "void value, overriding the file's" },
	{ 'n', "-n", "name", "the file name of a DEM on stdin (N42E001.hgt)" },
	{ 's', "-s", "dx[,dy]", "cell size in metres (overrides the CRS's "
	    "metric)" },
	{ DEM_RESAMPLE, "--resample", NULL, "let GDAL resample a VRT's scaled "
	    "sources, not refuse them" },
};
#define NDEMFLAGS (sizeof dem_flags / sizeof dem_flags[0])

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
	tl_out_catch(); /* before any thread: outfile.h */
}

/* The program's options and the shared ones, in one optstring and one
 * long option table (built once). */
static void
build(cli *c, const char *optstring, const struct option *longopts)
{
	size_t n = 0;

	size_t len;

	snprintf(c->optstring, sizeof c->optstring, "%shV%s",
	    optstring != NULL ? optstring : "",
	    c->sets & CLI_COMPRESSION ? "z:" : "");
	for (; longopts != NULL && longopts[n].name != NULL; n++) {
		assert(n + 2 + NDEMFLAGS < CLI_MAXLONG);
		c->longopts[n] = longopts[n];
	}
	c->longopts[n++] = shared_long[0];
	c->longopts[n++] = shared_long[1];
	for (size_t k = 0; c->sets & CLI_DEM && k < NDEMFLAGS; k++) {
		len = strlen(c->optstring);
		assert(len + 3 < sizeof c->optstring);
		if (dem_flags[k].flag[1] != '-')
			snprintf(c->optstring + len, sizeof c->optstring - len,
			    "%c%s", dem_flags[k].ch,
			    dem_flags[k].arg != NULL ? ":" : "");
		else
			c->longopts[n++] = (struct option){ dem_flags[k].flag +
			    2, dem_flags[k].arg != NULL ? required_argument :
			    no_argument, NULL, dem_flags[k].ch };
	}
	memset(&c->longopts[n], 0, sizeof c->longopts[n]);
}

/* A DEM option given, kept as argv words for the stages (-n aside). */
static void
remember_dem(cli *c, int ch, const char *arg)
{
	size_t k = 0;

	while (k < NDEMFLAGS && dem_flags[k].ch != ch)
		k++;
	assert(k < NDEMFLAGS);
	if (ch == 'n')
		return;
	if (c->ndemargv + 2 > CLI_MAXDEMARGV) {
		c->status = cli_bad(c, "too many DEM options");
		return;
	}
	c->demargv[c->ndemargv++] = dem_flags[k].flag;
	if (dem_flags[k].arg != NULL)
		c->demargv[c->ndemargv++] = arg;
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
		remember_dem(c, ch, arg);
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

/* The DEM options' lines of a usage, from the table. */
static void
dem_help(FILE *f)
{
	char name[32];

	for (size_t k = 0; k < NDEMFLAGS; k++) {
		snprintf(name, sizeof name, "%s%s%s", dem_flags[k].flag,
		    dem_flags[k].arg != NULL ? " " : "",
		    dem_flags[k].arg != NULL ? dem_flags[k].arg : "");
		fprintf(f, "  %-16s", name);
		for (const char *p = dem_flags[k].help; *p != '\0'; p++)
			if (*p == '\n')
				fprintf(f, "\n%18s", "");
			else
				fputc(*p, f);
		fputc('\n', f);
	}
}

void
cli_usage(const cli *c, FILE *f)
{
	const char *mark = strstr(c->usage, CLI_DEM_HELP);

	fprintf(f, "usage: %s ", c->prog);
	if (mark == NULL) {
		fputs(c->usage, f);
		return;
	}
	fwrite(c->usage, 1, (size_t)(mark - c->usage), f);
	dem_help(f);
	fputs(mark + 1, f);
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
cli_outdir(const cli *c, const char *dir)
{
	if (strcmp(dir, "-") != 0)
		return 0;
	return cli_bad(c, "-: the output is a directory, which standard "
	    "output cannot hold (./- names a directory -)");
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

	if (tl_parse_ll(s, &v) == 0 && v >= lo && v <= hi)
		return v;
	c->status = cli_bad(c, "%s %s: not an integer in %lld .. %lld", opt,
	    s, lo, hi);
	return lo;
}

double
cli_real(cli *c, const char *opt, const char *s, double lo, double hi)
{
	double v;

	if (tl_parse_double(s, &v) == 0 && isfinite(v) && v >= lo && v <= hi)
		return v;
	c->status = cli_bad(c, "%s %s: not a number in %g .. %g", opt, s, lo,
	    hi);
	return lo;
}

const char *
cli_bindir(char *buf, size_t n)
{
	const char *env = getenv("TL_BIN");
	ssize_t r;
	char *slash;

	if (env != NULL && env[0] != '\0')
		return env;
	if ((r = readlink("/proc/self/exe", buf, n - 1)) <= 0)
		return NULL;
	buf[r] = '\0';
	if ((slash = strrchr(buf, '/')) == NULL)
		return NULL;
	*slash = '\0';
	return buf;
}

int
cli_jobs(void)
{
	long n = sysconf(_SC_NPROCESSORS_ONLN);

	return n < 1 ? 1 : n > CLI_JOBS_MAX ? CLI_JOBS_MAX : (int)n;
}
