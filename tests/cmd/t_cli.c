/* t_cli - the programs' shared start-up (cli.h): the name from argv[0]
 * (and argv[0] rewritten, so getopt's messages say the same), -h/-V and
 * their long forms, the shared -z and DEM options beside a program's own,
 * usage errors (status 2), operands and exit statuses. */
#include "cli.h"
#include "tap.h"

#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char dir[PATH_MAX / 2];
static char captured[4096];
static int saved = -1, target;

/* Captures what is written on fd (1 or 2) until capture_end. */
static void
capture_begin(int fd)
{
	char path[PATH_MAX];
	int t;

	fflush(stdout), fflush(stderr);
	snprintf(path, sizeof path, "%s/captured", dir);
	t = open(path, O_CREAT | O_TRUNC | O_RDWR, 0644);
	target = fd;
	saved = dup(fd);
	dup2(t, fd);
	close(t);
}

static const char *
capture_end(void)
{
	char path[PATH_MAX];
	ssize_t n;
	int t;

	fflush(stdout), fflush(stderr);
	dup2(saved, target);
	close(saved);
	snprintf(path, sizeof path, "%s/captured", dir);
	t = open(path, O_RDONLY);
	n = t >= 0 ? read(t, captured, sizeof captured - 1) : -1;
	captured[n > 0 ? n : 0] = '\0';
	if (t >= 0)
		close(t);
	unlink(path);
	return captured;
}

/* Runs cli_next to the end over argv (argc entries), collecting the
 * program's option characters (and each one's argument) in got. */
static int
parse(cli *c, int argc, char **argv, const char *opts,
    const struct option *longopts, char *got, const char **arg)
{
	int ch, n = 0;

	optind = 0; /* glibc: start over */
	while ((ch = cli_next(c, argc, argv, opts, longopts)) != -1) {
		got[n++] = (char)ch;
		*arg = optarg;
	}
	got[n] = '\0';
	return c->status;
}

static void
test_name(void)
{
	char a0[] = "/usr/local/bin/../build/dem2fqm", a1[] = "fqmsolve";
	char a2[] = "odd/";
	char *argv[] = { a0, NULL };
	cli c;

	cli_init(&c, argv, "in out\n", 0);
	ok(strcmp(c.prog, "dem2fqm") == 0 && argv[0] == c.prog &&
	    strcmp(argv[0], "dem2fqm") == 0, "cli_init: the name is argv[0]'s "
	    "last component, and argv[0] says it too");
	ok(c.status == -1 && c.comp == RS_ZIP && c.dem.cell[0] == 0 &&
	    c.dem.heights == NULL, "cli_init: no status yet, ZIP, no DEM "
	    "option");
	argv[0] = a1;
	cli_init(&c, argv, "", 0);
	ok(strcmp(c.prog, "fqmsolve") == 0, "cli_init: a bare name as it is");
	argv[0] = a2;
	cli_init(&c, argv, "", 0);
	ok(strcmp(c.prog, "odd/") == 0, "cli_init: a name ending in / kept "
	    "whole rather than empty");
}

static void
test_shared(void)
{
	char a0[] = "./build/dem2fqm", *argv[16];
	static const struct option longopts[] = {
		{ "tau", required_argument, NULL, 't' }, { NULL, 0, NULL, 0 },
	};
	const char *arg = NULL;
	char got[16];
	cli c;
	int n = 0;

	argv[n++] = a0;
	for (const char *const *s = (const char *const[]){ "-z", "piz", "-s",
	    "30,20", "-e", "terrarium", "-x", "7", "-H", "ellipsoid", "-N",
	    "-9999", "in.tif", "out.exr", NULL }; *s != NULL; s++)
		argv[n++] = (char *)*s;
	argv[n] = NULL;
	cli_init(&c, argv, "[-x n] in out\n", CLI_COMPRESSION | CLI_DEM);
	ok(parse(&c, n, argv, "x:", longopts, got, &arg) == -1 &&
	    strcmp(got, "x") == 0 && strcmp(arg, "7") == 0,
	    "cli_next: only the program's own option comes back (-x 7)");
	ok(c.comp == RS_PIZ && c.dem.cell[0] == 30 && c.dem.cell[1] == 20 &&
	    c.dem.encoding == DEM_ENC_TERRARIUM && c.dem.has_nodata &&
	    c.dem.nodata == -9999 && strcmp(c.dem.heights, "ellipsoid") == 0,
	    "cli_next: -z and the DEM options (-s -e -H -N) handled "
	    "in the struct");
	ok(optind == n - 2 && strcmp(argv[optind], "in.tif") == 0,
	    "cli_next: optind at the operands");
	argv[1] = "--tau", argv[2] = "0.5", argv[3] = NULL;
	cli_init(&c, argv, "", 0);
	ok(parse(&c, 3, argv, "", longopts, got, &arg) == -1 &&
	    strcmp(got, "t") == 0 && strcmp(arg, "0.5") == 0,
	    "cli_next: the program's long options");
}

static void
test_help(void)
{
	char a0[] = "/x/fqmfilter", *argv[] = { a0, "-h", "-x", NULL };
	const char *arg, *out;
	char got[16];
	cli c;
	int st;

	cli_init(&c, argv, "[-k kernel] [in [out]]\n", CLI_COMPRESSION);
	capture_begin(STDOUT_FILENO);
	st = parse(&c, 3, argv, "k:", NULL, got, &arg);
	out = capture_end();
	ok(st == CLI_OK && got[0] == '\0' &&
	    strcmp(out, "usage: fqmfilter [-k kernel] [in [out]]\n") == 0,
	    "-h: the usage on stdout, status 0, nothing after it parsed");
	argv[1] = "--version";
	cli_init(&c, argv, "", 0);
	capture_begin(STDOUT_FILENO);
	st = parse(&c, 2, argv, "", NULL, got, &arg);
	out = capture_end();
	ok(st == CLI_OK && strcmp(out, "fqmfilter " TL_VERSION "\n") == 0,
	    "--version: \"name version\" on stdout, status 0 (%.*s)",
	    (int)strcspn(out, "\n"), out);
	argv[1] = "--help";
	cli_init(&c, argv, "in\n", 0);
	capture_begin(STDOUT_FILENO);
	st = parse(&c, 2, argv, "", NULL, got, &arg);
	out = capture_end();
	ok(st == CLI_OK && strcmp(out, "usage: fqmfilter in\n") == 0,
	    "--help as -h");
}

static void
test_usage(void)
{
	char a0[] = "/some/where/fqmsolve", *argv[] = { a0, "-q", NULL, NULL };
	const char *arg, *err;
	char got[16];
	cli c;
	int st;

	cli_init(&c, argv, "[-m mode] [in [out]]\n", CLI_COMPRESSION);
	capture_begin(STDERR_FILENO);
	st = parse(&c, 2, argv, "m:", NULL, got, &arg);
	err = capture_end();
	ok(st == CLI_USAGE && strncmp(err, "fqmsolve: ", 10) == 0 &&
	    strstr(err, "usage: fqmsolve [-m mode]") != NULL &&
	    strstr(err, "/some/where") == NULL, "an unknown option: status 2, "
	    "getopt's message and the usage under one name (%.*s)",
	    (int)strcspn(err, "\n"), err);
	argv[1] = "-z", argv[2] = "lzw";
	cli_init(&c, argv, "x\n", CLI_COMPRESSION);
	capture_begin(STDERR_FILENO);
	st = parse(&c, 3, argv, "", NULL, got, &arg);
	err = capture_end();
	ok(st == CLI_USAGE && strcmp(err, "fqmsolve: -z lzw: unknown "
	    "compression\n") == 0, "-z with a bad value: status 2 (%.*s)",
	    (int)strcspn(err, "\n"), err);
	argv[1] = "-z", argv[2] = "zip";
	cli_init(&c, argv, "x\n", 0);
	capture_begin(STDERR_FILENO);
	st = parse(&c, 3, argv, "", NULL, got, &arg);
	capture_end();
	ok(st == CLI_USAGE, "-z where the program takes no compression: an "
	    "unknown option");
	argv[1] = "-s", argv[2] = "-3";
	cli_init(&c, argv, "x\n", CLI_DEM);
	capture_begin(STDERR_FILENO);
	st = parse(&c, 3, argv, "", NULL, got, &arg);
	err = capture_end();
	ok(st == CLI_USAGE && strstr(err, "fqmsolve: -s -3: ") == err,
	    "a bad DEM option value: status 2 (%.*s)",
	    (int)strcspn(err, "\n"), err);
	argv[1] = "-m", argv[2] = NULL;
	cli_init(&c, argv, "x\n", 0);
	capture_begin(STDERR_FILENO);
	st = parse(&c, 2, argv, "m:", NULL, got, &arg);
	err = capture_end();
	ok(st == CLI_USAGE && strstr(err, "fqmsolve: option requires an "
	    "argument") == err, "a missing argument: status 2");
}

static void
test_operands_exit(void)
{
	char a0[] = "dem2fqm", in[PATH_MAX];
	char *argv[] = { a0, NULL }, *three[] = { "a", "b", "c" };
	char *same[] = { in, in }, *two[] = { in, "o.exr" };
	const char *i = NULL, *o = NULL, *err;
	tl_err e;
	cli c;
	int st;

	snprintf(in, sizeof in, "%s/in.exr", dir);
	close(open(in, O_CREAT | O_WRONLY, 0644));
	cli_init(&c, argv, "[in [out]]\n", 0);
	ok(cli_operands(&c, 2, two, &i, &o) == 0 && i == in &&
	    strcmp(o, "o.exr") == 0, "cli_operands: in and out");
	capture_begin(STDERR_FILENO);
	st = cli_operands(&c, 3, three, &i, &o);
	err = capture_end();
	ok(st == CLI_USAGE && strcmp(err, "usage: dem2fqm [in [out]]\n") == 0,
	    "cli_operands: three operands, status 2 and the usage");
	capture_begin(STDERR_FILENO);
	st = cli_operands(&c, 2, same, &i, &o);
	err = capture_end();
	ok(st == CLI_FAIL && strstr(err, "dem2fqm: ") == err &&
	    strstr(err, "both the input and the output"), "cli_operands: "
	    "the same file in and out, status 1 (%.*s)",
	    (int)strcspn(err, "\n"), err);
	unlink(in);
	tl_fail(&e, "x.tif: no such DEM");
	capture_begin(STDERR_FILENO);
	st = cli_exit(&c, -1, &e);
	err = capture_end();
	ok(st == CLI_FAIL && strcmp(err, "dem2fqm: x.tif: no such DEM\n") == 0,
	    "cli_exit: a failure is \"prog: what: why\" and status 1");
	capture_begin(STDERR_FILENO);
	st = cli_exit(&c, 0, &e);
	err = capture_end();
	ok(st == CLI_OK && err[0] == '\0', "cli_exit: success is status 0, "
	    "silent");
	capture_begin(STDERR_FILENO);
	st = cli_bad(&c, "-k %s: unknown kernel", "gauss");
	err = capture_end();
	ok(st == CLI_USAGE && strcmp(err, "dem2fqm: -k gauss: unknown "
	    "kernel\n") == 0, "cli_bad: the message and status 2");
}

/* cli_filter_args: the status to exit with now, or -1 with operands */
static void
test_filter_args(void)
{
	char a0[] = "fqmsolve", h[] = "-h", op1[] = "in.exr", op2[] = "-";
	char *help[] = { a0, h, NULL }, *args[] = { a0, op1, op2, NULL };
	char *many[] = { a0, op1, op1, op1, NULL };
	const char *i = NULL, *o = NULL, *err;
	char got[8];
	const char *arg;
	cli c;
	int st;

	cli_init(&c, help, "[in [out]]\n", CLI_COMPRESSION);
	capture_begin(STDOUT_FILENO);
	parse(&c, 2, help, "", NULL, got, &arg);
	st = cli_filter_args(&c, 2, help, &i, &o);
	capture_end();
	ok(st == CLI_OK, "cli_filter_args after --help: exit now, status 0");
	cli_init(&c, args, "[in [out]]\n", CLI_COMPRESSION);
	parse(&c, 3, args, "", NULL, got, &arg);
	capture_begin(STDOUT_FILENO);
	st = cli_filter_args(&c, 3, args, &i, &o);
	capture_end();
	/* stdout captured into a file: "-" is not a terminal */
	ok(st == -1 && strcmp(i, "in.exr") == 0 && strcmp(o, "-") == 0,
	    "cli_filter_args: go on, with in and out (%d)", st);
	cli_init(&c, many, "[in [out]]\n", 0);
	parse(&c, 4, many, "", NULL, got, &arg);
	capture_begin(STDERR_FILENO);
	st = cli_filter_args(&c, 4, many, &i, &o);
	err = capture_end();
	ok(st == CLI_USAGE && strstr(err, "usage: fqmsolve") == err,
	    "cli_filter_args: three operands, status 2 and the usage");
}

/* cli_number, cli_real: a value in its range, or "opt s: why" and
 * status 2 (the next cli_next then returns -1); cli_jobs in range. */
static void
test_numbers(void)
{
	char a0[] = "tilepack", *argv[] = { a0, NULL };
	const char *err;
	long long v;
	double d;
	cli c;

	cli_init(&c, argv, "x\n", 0);
	ok(cli_number(&c, "-j", "12", 1, 1024) == 12 && c.status == -1 &&
	    cli_real(&c, "-t", "2.5e-1", 0, 1e6) == 0.25 && c.status == -1,
	    "cli_number, cli_real: values in range, no status");
	ok(cli_number(&c, "-b", "0", 0, 9) == 0 && cli_number(&c, "-b", "9",
	    0, 9) == 9 && c.status == -1, "cli_number: both ends included");
	capture_begin(STDERR_FILENO);
	v = cli_number(&c, "-j", "0", 1, 1024);
	err = capture_end();
	ok(v == 1 && c.status == CLI_USAGE && strcmp(err, "tilepack: -j 0: "
	    "not an integer in 1 .. 1024\n") == 0, "cli_number: out of "
	    "range, status 2, lo returned (%.*s)", (int)strcspn(err, "\n"),
	    err);
	for (const char *const *bad = (const char *const[]){ "x", "3x", "",
	    "1.5", "99999999999999999999", NULL }; *bad != NULL; bad++) {
		cli_init(&c, argv, "x\n", 0);
		capture_begin(STDERR_FILENO);
		(void)cli_number(&c, "--band-rows", *bad, 1, INT_MAX);
		err = capture_end();
		ok(c.status == CLI_USAGE && strstr(err, "--band-rows ") != NULL &&
		    strstr(err, "not an integer") != NULL, "cli_number: \"%s\" "
		    "refused", *bad);
	}
	for (const char *const *bad = (const char *const[]){ "nan", "inf",
	    "-1", "2", "x", NULL }; *bad != NULL; bad++) {
		cli_init(&c, argv, "x\n", 0);
		capture_begin(STDERR_FILENO);
		d = cli_real(&c, "-r", *bad, 0, 1);
		err = capture_end();
		ok(d == 0 && c.status == CLI_USAGE && strstr(err, "tilepack: -r ")
		    == err && strstr(err, "not a number in 0 .. 1") != NULL,
		    "cli_real: \"%s\" refused", *bad);
	}
	ok(cli_jobs() >= 1 && cli_jobs() <= CLI_JOBS_MAX, "cli_jobs: 1 .. "
	    "CLI_JOBS_MAX (%d)", cli_jobs());
}

/* The DEM options: one table parses them, writes their usage lines and
 * gives them back as argv words for a stage, in order, -n aside. */
static void
test_dem_table(void)
{
	char a0[] = "dem2vgis", *argv[16];
	const char *arg, *out;
	char got[8];
	cli c;
	int n = 0;

	argv[n++] = a0;
	for (const char *const *s = (const char *const[]){ "-N", "-32768",
	    "-n", "x.hgt", "--resample", "-s", "30", "-H", "EPSG:5773",
	    "dem", NULL }; *s != NULL; s++)
		argv[n++] = (char *)*s;
	argv[n] = NULL;
	cli_init(&c, argv, "[-x] dem\n" CLI_DEM_HELP "  dem   the DEM\n",
	    CLI_DEM);
	ok(parse(&c, n, argv, "", NULL, got, &arg) == -1 && got[0] == '\0' &&
	    c.dem.resample && strcmp(c.dem.hgt_name, "x.hgt") == 0,
	    "the DEM options, --resample too, parsed by the shared table");
	ok(cli_dem_argc(&c) == 7 && strcmp(cli_dem_argv(&c)[0], "-N") == 0 &&
	    strcmp(cli_dem_argv(&c)[1], "-32768") == 0 &&
	    strcmp(cli_dem_argv(&c)[2], "--resample") == 0 &&
	    strcmp(cli_dem_argv(&c)[3], "-s") == 0 &&
	    strcmp(cli_dem_argv(&c)[4], "30") == 0 &&
	    strcmp(cli_dem_argv(&c)[5], "-H") == 0 &&
	    strcmp(cli_dem_argv(&c)[6], "EPSG:5773") == 0,
	    "cli_dem_argv: the words as given, in order, -n aside (%d)",
	    cli_dem_argc(&c));
	capture_begin(STDOUT_FILENO);
	cli_usage(&c, stdout);
	out = capture_end();
	ok(strncmp(out, "usage: dem2vgis [-x] dem\n  -D datum        the "
	    "DEM's", 50) == 0 && strstr(out, "\n  --resample      let GDAL") !=
	    NULL && strstr(out, "\n  -s dx[,dy]      cell size") != NULL &&
	    strstr(out, "them\n  dem   the DEM\n") != NULL &&
	    strchr(out, '\001') == NULL, "cli_usage: the table's lines where "
	    "the usage marks them");
}

int
main(void)
{
	const char *t = getenv("TMPDIR");

	snprintf(dir, sizeof dir, "%s/t_cli.XXXXXX", t && *t ? t : "/tmp");
	if (mkdtemp(dir) == NULL) {
		perror(dir);
		return 1;
	}
	test_name();
	test_shared();
	test_help();
	test_usage();
	test_operands_exit();
	test_filter_args();
	test_numbers();
	test_dem_table();
	rmdir(dir);
	return tap_done();
}
