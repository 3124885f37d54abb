/* cli.h - what every program does the same way at start-up (netpbm's
 * pm_proginit, OpenBSD's getprogname): its name from argv[0], -h/--help,
 * -V/--version, the shared option sets (-z compression, the DEM options),
 * the filters' "[in [out]]" operands, messages and exit codes:
 * 0 done, 1 failed, 2 usage. A program parses into its own struct with
 * cli_next as it would with getopt_long, and ends with cli_exit. */
#ifndef TL_CLI_H
#define TL_CLI_H

#include <getopt.h>
#include <stdio.h>

#include "dem/dem.h"
#include "raster/raster.h"
#include "base/util.h"

enum { CLI_OK = 0, CLI_FAIL = 1, CLI_USAGE = 2 };

/* Shared option sets a program may take. */
#define CLI_COMPRESSION 1 /* -z compression of an EXR output */
#define CLI_DEM 2         /* DEM_OPTS: -e -N -n -s -H -D */

#define CLI_MAXLONG 40
#define CLI_MAXDEMARGV 32

/* In a usage text, where the DEM options' lines go (cli_usage writes
 * them from the table of cli.c, the one place they are described). */
#define CLI_DEM_HELP "\001"

typedef struct {
	const char *prog;          /* argv[0]'s last component */
	const char *usage;         /* what follows "usage: prog " */
	int sets;                  /* CLI_COMPRESSION | CLI_DEM */
	enum rs_compression comp;  /* -z; RS_ZIP unless given */
	dem_opts dem;              /* the DEM options */
	const char *demargv[CLI_MAXDEMARGV]; /* and as given, -n aside */
	int ndemargv;
	int status;                /* -1, or the status to exit with now */
	char optstring[128];
	struct option longopts[CLI_MAXLONG];
} cli;

/* Names the program after argv[0]'s last component and sets argv[0] to
 * it, so that getopt's messages and ours say the same name. usage is the
 * text after "usage: prog ": the synopsis and the option list. Ignores
 * SIGXFSZ (a write over ulimit -f fails with EFBIG, and the failure path
 * cleans up) and checks at exit that stdout took every write: when one
 * failed, "prog: stdout: why" and exit status 1, unless cli_exit has
 * reported a failure already. */
void cli_init(cli *c, char **argv, const char *usage, int sets);

/* getopt_long over the program's options (optstring, and longopts ending
 * in a zero entry, or NULL) and the shared ones, which it handles itself.
 * Returns the program's next option character (or a long option's val),
 * or -1 when the options end or when the program must exit now with
 * c->status: after --help or --version (0), an unknown option or a bad
 * value of a shared one (2). */
int cli_next(cli *c, int argc, char **argv, const char *optstring,
    const struct option *longopts);

/* The usage, on stdout for --help, on stderr for a usage error; where
 * it holds CLI_DEM_HELP, the DEM options, a line each. */
void cli_usage(const cli *c, FILE *f);

/* A usage error: the usage on stderr; returns CLI_USAGE. */
int cli_usage_error(const cli *c);

/* An output directory operand: "-" refused (a usage error, its status
 * returned), since standard output cannot hold a directory and a
 * directory named "-" is seldom meant (./- names one); else 0. */
int cli_outdir(const cli *c, const char *dir);
/* A bad option value or operand: "prog: message"; returns CLI_USAGE. */
int cli_bad(const cli *c, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* "prog: message" on stderr, for warnings and failures. */
void cli_warn(const cli *c, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* A filter's operands "[in [out]]", "-" by default: 0, or the status to
 * exit with (2 for more than two, 1 for a stream to a terminal or the
 * same file in and out, with a message). */
int cli_operands(const cli *c, int argc, char **argv, const char **in,
    const char **out);

/* After a filter's options: the status to exit with now (after --help
 * or --version, a usage error, bad operands), or -1 to go on with the
 * operands in *in and *out. */
int cli_filter_args(const cli *c, int argc, char **argv, const char **in,
    const char **out);

/* A numeric option's value, as OpenBSD's strtonum: an integer (cli_number)
 * or a finite real (cli_real) in lo .. hi. Out of range or not a number:
 * "prog: opt s: not an integer in lo .. hi" ("not a number" for a real)
 * on stderr, c->status set to CLI_USAGE (so
 * that the next cli_next returns -1) and lo returned. opt names the
 * option as the user wrote it ("-j", "--band-width"). */
long long cli_number(cli *c, const char *opt, const char *s, long long lo,
    long long hi);
double cli_real(cli *c, const char *opt, const char *s, double lo,
    double hi);

/* The default of -j: the CPUs online, at least 1, at most CLI_JOBS_MAX. */
#define CLI_JOBS_MAX 1024
int cli_jobs(void);

/* The DEM options given (-n aside, which a supervisor passes on only
 * for a named DEM), as argv words for a stage that reads the DEM too:
 * the options' names from the table that parsed them, their values as
 * given, in order. */
#define cli_dem_argv(c) ((c)->demargv)
#define cli_dem_argc(c) ((c)->ndemargv)

/* The directory of this program, where the stages are installed beside
 * it (or the build tree it runs from); TL_BIN, when set, first. NULL
 * when unknown (then PATH). */
const char *cli_bindir(char *buf, size_t n);

/* Columns "a,b" (-w, -C: a .. b-1, 0 <= a < b): 0, or -1. */
int cli_columns(const char *s, int r[2]);

/* The exit status of a work function's result: 0 when r >= 0, else 1
 * after "prog: what: why" from e. */
int cli_exit(const cli *c, int r, const tl_err *e);

#endif
