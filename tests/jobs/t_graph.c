/* t_graph - the supervisor (graph.h) with ordinary Unix programs as
 * stages: pipes carry the data, the in-process tee copies to both sides,
 * a captured stdout; the first failure ends the rest quickly and only its
 * message comes back; a stage that dies of a signal is said so; follow-on
 * failures (a writer whose reader is gone) are not the cause; warnings of
 * stages that end well pass; progress lines arrive whole. */
#include "jobs/graph.h"
#include "tap.h"

#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static char dir[256];

static const char *
tmp(const char *name)
{
	static char buf[4][512];
	static int k;

	k = (k + 1) % 4;
	snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
	return buf[k];
}

static double
now(void)
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + t.tv_nsec / 1e9;
}

static int
sh(graph *g, const char *script, int in, int out, tl_err *e)
{
	char *argv[] = { "sh", "-c", (char *)script, NULL };

	return graph_exec(g, argv, in, out, e);
}

static char *
slurp(const char *path)
{
	static char buf[1 << 16];
	int fd = open(path, O_RDONLY);
	ssize_t n = fd < 0 ? -1 : read(fd, buf, sizeof buf - 1);

	if (fd >= 0)
		close(fd);
	buf[n > 0 ? n : 0] = '\0';
	return buf;
}

/* seq | tee | (wc -l > a), (sum > b): both sides get every byte */
static void
test_tee(void)
{
	graph *g;
	tl_err e;
	int p[2], q1[2], q2[2], a, b, st;

	g = graph_new("t_graph", NULL, &e);
	graph_pipe(g, p, &e), graph_pipe(g, q1, &e), graph_pipe(g, q2, &e);
	a = graph_open(g, tmp("a"), O_WRONLY | O_CREAT | O_TRUNC, 0600, &e);
	b = graph_open(g, tmp("b"), O_WRONLY | O_CREAT | O_TRUNC, 0600, &e);
	sh(g, "seq 1 200000", -1, p[1], &e);
	graph_tee(g, p[0], q1[1], q2[1], &e);
	sh(g, "wc -l", q1[0], a, &e);
	sh(g, "cksum", q2[0], b, &e);
	ok(graph_run(g, &st, &e) == 0 && st == 0, "seq | tee | wc, cksum: all end well");
	graph_free(g);
	ok(atoi(slurp(tmp("a"))) == 200000, "the first side got every line (%s)",
	    slurp(tmp("a")));
	char want[64] = "";
	FILE *f = popen("seq 1 200000 | cksum", "r");
	if (f == NULL || fgets(want, sizeof want, f) == NULL)
		want[0] = '\0';
	if (f != NULL)
		pclose(f);
	ok(want[0] && strcmp(slurp(tmp("b")), want) == 0,
	    "the second side got every byte (%.30s)", want);
}

static void
test_capture(void)
{
	char buf[64];
	graph *g = graph_new("t_graph", NULL, NULL);
	tl_err e;
	int k, st;

	k = sh(g, "echo levels 5; echo more", -1, -1, &e);
	graph_capture(g, k, buf, 10, &e);
	ok(graph_run(g, &st, &e) == 0, "a captured stage ends well");
	ok(strcmp(buf, "levels 5\n") == 0, "its stdout, cut to the buffer: "
	    "\"%s\"", buf);
	graph_free(g);
}

/* A stage fails while others would run for a minute: all end within
 * seconds, its message alone comes back with its status. */
static void
test_first_failure(void)
{
	graph *g = graph_new("t_graph", NULL, NULL);
	tl_err e;
	int p[2], st;
	double t0 = now();

	graph_pipe(g, p, &e);
	sh(g, "yes", -1, p[1], &e);	/* dies of SIGPIPE: a follow-on */
	sh(g, "head -c 1000 >/dev/null; echo 'b: made to fail' >&2; exit 3", p[0], -1, &e);
	sh(g, "echo 'c: interrupted' >&2; sleep 60", -1, -1, &e);
	sh(g, "trap '' TERM; sleep 60", -1, -1, &e);	/* ignores SIGTERM */
	ok(graph_run(g, &st, &e) < 0, "a failing stage fails the graph");
	ok(strcmp(e.msg, "b: made to fail") == 0, "its message alone: \"%s\"", e.msg);
	ok(st == 3, "its exit status: %d", st);
	ok(now() - t0 < 10, "everything stopped in %.1f s (SIGKILL after 1 s "
	    "for the one ignoring SIGTERM)", now() - t0);
	graph_free(g);
}

/* A writer that fails after its output has ended (a full disk under its
 * scratch file): the reader two pipes down (through a tee) fails first,
 * on short input, yet the cause told is the writer's. */
/* A tee's reader that fails and closes its input, slow to exit (a
 * scratch removed): the tee dies of the closed pipe, its other reader
 * fails first on short input, yet the cause told is the reader that
 * closed (dem2vgis's processes under load: fqmfilter's "truncated"
 * told instead of fqmsolve's "File too large"). */
static void
test_sibling_cause(void)
{
	graph *g = graph_new("t_graph", NULL, NULL);
	tl_err e;
	int p[2], q1[2], q2[2], st;

	graph_pipe(g, p, &e);
	graph_pipe(g, q1, &e);
	graph_pipe(g, q2, &e);
	sh(g, "exec seq 1 10000000", -1, p[1], &e);
	graph_tee(g, p[0], q1[1], q2[1], &e);
	sh(g, "n=$(wc -l); echo \"c: truncated at $n\" >&2; exit 1", q1[0], -1,
	    &e);
	sh(g, "trap '' TERM; head -c 1000 >/dev/null; exec <&-; sleep 0.3; "
	    "echo 'b: disk full' >&2; exit 4", q2[0], -1, &e);
	int r = graph_run(g, &st, &e);
	ok(r < 0 && strcmp(e.msg, "b: disk full") == 0 && st == 4, "a tee's "
	    "reader failing on short input: the other reader, which closed "
	    "first, is the cause (\"%s\", status %d)", e.msg, st);
	graph_free(g);
}

static void
test_upstream_cause(void)
{
	graph *g = graph_new("t_graph", NULL, NULL);
	tl_err e;
	int p[2], q[2], st;

	graph_pipe(g, p, &e);
	graph_pipe(g, q, &e);
	sh(g, "exec >&-; sleep 0.3; echo 'a: disk full' >&2; exit 4", -1, p[1], &e);
	graph_tee(g, p[0], q[1], -1, &e);
	sh(g, "cat >/dev/null; echo 'c: empty input' >&2; exit 1", q[0], -1, &e);
	int r = graph_run(g, &st, &e);
	ok(r < 0 && strcmp(e.msg, "a: disk full") == 0 && st == 4, "a reader failing on short input: the writer upstream "
	    "is the cause (\"%s\", status %d)", e.msg, st);
	graph_free(g);
}

static void
test_signal_death(void)
{
	graph *g = graph_new("t_graph", NULL, NULL);
	tl_err e;
	int st;

	sh(g, "kill -SEGV $$", -1, -1, &e);
	int r = graph_run(g, &st, &e);
	ok(r < 0 && strstr(e.msg, "killed by signal 11") && st == 1,
	    "a stage killed by a signal: \"%s\", status %d", e.msg, st);
	graph_free(g);
}

static void
test_missing_program(void)
{
	char *argv[] = { "no-such-program-tl", NULL };
	graph *g = graph_new("t_graph", NULL, NULL);
	tl_err e;
	int st;

	graph_exec(g, argv, -1, -1, &e);
	int r = graph_run(g, &st, &e);
	ok(r < 0 && strstr(e.msg, "no-such-program-tl") &&
	    strstr(e.msg, "No such file"), "a missing program: \"%s\"", e.msg);
	graph_free(g);
}

/* bindir is searched before PATH */
static void
test_bindir(void)
{
	char buf[64], *argv[] = { "hello-tl", NULL };
	graph *g = graph_new("t_graph", dir, NULL);
	tl_err e;
	int k, fd, st;

	fd = open(tmp("hello-tl"), O_WRONLY | O_CREAT | O_TRUNC, 0755);
	write(fd, "#!/bin/sh\necho from bindir\n", 27);
	close(fd);
	k = graph_exec(g, argv, -1, -1, &e);
	graph_capture(g, k, buf, sizeof buf, &e);
	ok(graph_run(g, &st, &e) == 0 && strcmp(buf, "from bindir\n") == 0,
	    "a stage found in bindir: %s", buf);
	graph_free(g);
}

typedef struct {
	int n, whole;
	long long last;
} seen;

static void
on_progress(void *ctx, const char *label, long long done, long long total)
{
	seen *s = ctx;

	s->n++;
	s->whole += strcmp(label, "stage") == 0 && total == 100 && done >= s->last;
	s->last = done;
}

static void
test_progress(void)
{
	graph *g = graph_new("t_graph", NULL, NULL);
	seen s = { 0 };
	tl_err e;
	int st;

	graph_progress(g, on_progress, &s);
	sh(g, "[ \"$TL_PROGRESS_FD\" = 3 ] || exit 1; i=0; while [ $i -le 100 ]; do "
	    "printf 'stage\\t%d\\t100\\n' $i >&3; i=$((i + 5)); done", -1, -1, &e);
	ok(graph_run(g, &st, &e) == 0, "a stage reports progress on TL_PROGRESS_FD");
	ok(s.n == 21 && s.whole == 21, "every line arrives whole, in order "
	    "(%d lines, %d whole)", s.n, s.whole);
	graph_free(g);
}

int
main(void)
{
	snprintf(dir, sizeof dir, "%s/t_graph.XXXXXX",
	    getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (mkdtemp(dir) == NULL)
		return 2;
	test_tee();
	test_capture();
	test_first_failure();
	test_upstream_cause();
	test_sibling_cause();
	test_signal_death();
	test_missing_program();
	test_bindir();
	test_progress();
	char cmd[600];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	system(cmd);
	return tap_done();
}
