/* t_outfile_signal - a fatal signal sent to a process whose threads are
 * making temporaries (outfile.h) leaves none behind, whichever thread
 * the kernel hands the signal to: the handler waits for the temporaries
 * under way to be registered. Each round forks a child whose worker
 * threads make and abort temporaries in a loop while its main thread
 * waits (so the signal usually lands there, not in a maker), and kills
 * it with SIGTERM after a random delay; then the directory must be
 * empty. Before the wait, 46 rounds of 60 left a temporary; with the
 * wait but the handler installed only with the first output, 1 to 7
 * (the default action met a thread inside the call making its first).
 * Then the same with files made under their final names inside a tree
 * the child builds (tl_out_begin_tree): the handler must find every
 * file there made before it removes the tree, or the tree stays. */
#include "base/outfile.h"
#include "base/rmtree.h"
#include "tap.h"
#include "tmpdir.h"

#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define ROUNDS 60
#define MAKERS 3

static char dir[256];
static char tree[512]; /* the child's tree, in the tree rounds */

static void *
maker(void *arg)
{
	char p[512];
	tl_outfile o;
	tl_err e;

	snprintf(p, sizeof p, "%s/f%ld", dir, (long)arg);
	for (;;) {
		if (tl_out_begin_fresh(&o, p, &e) == 0)
			tl_out_abort(&o);
	}
	return NULL;
}

/* Files under new final names in the tree, kept: the tree fills. */
static void *
tree_maker(void *arg)
{
	char p[1024];
	tl_outfile o;
	tl_err e;

	for (long n = 0;; n++) {
		snprintf(p, sizeof p, "%s/f%ld-%ld", tree, (long)arg, n);
		if (tl_out_begin_tree(&o, p, &e) == 0 &&
		    write(o.fd, "x", 1) == 1)
			tl_out_commit(&o, &e);
	}
	return NULL;
}

/* The child: makers until the signal ends it. */
static void
child(int in_tree)
{
	pthread_t t[MAKERS];
	tl_outfile d;
	char p[512];

	tl_out_catch(); /* as every program's cli_init does */
	if (in_tree) {
		snprintf(p, sizeof p, "%s/t", dir);
		if (tl_outdir_begin(&d, p, NULL) < 0)
			_exit(3);
		snprintf(tree, sizeof tree, "%s", d.tmp);
	}
	for (long k = 0; k < MAKERS; k++)
		pthread_create(&t[k], NULL, in_tree ? tree_maker : maker,
		    (void *)k);
	pthread_join(t[0], NULL);
	_exit(0);
}

/* ROUNDS children killed: how many died of the signal, how many left
 * something (prefix: what counts, "" everything). */
static void
rounds(int in_tree, const char *prefix, int *killed, int *dirty)
{
	*killed = *dirty = 0;
	for (int r = 0; r < ROUNDS; r++) {
		struct timespec ts = { 0, 2000000 + rand() % 3000000 };
		int st;
		pid_t pid = fork();
		if (pid == 0)
			child(in_tree);
		nanosleep(&ts, NULL);
		kill(pid, SIGTERM);
		waitpid(pid, &st, 0);
		*killed += WIFSIGNALED(st) && WTERMSIG(st) == SIGTERM;
		if (tmpdir_entries(dir, prefix) != 0) {
			(*dirty)++;
			tl_rmtree(dir);
			mkdir(dir, 0700);
		}
	}
}

int
main(void)
{
	int dirty, killed;

	snprintf(dir, sizeof dir, "%s/t_outfile_signal.XXXXXX",
	    getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (mkdtemp(dir) == NULL)
		return 2;
	srand(7);
	rounds(0, ".f", &killed, &dirty);
	ok(killed == ROUNDS, "every child ended by its SIGTERM (%d of %d)",
	    killed, ROUNDS);
	ok(dirty == 0, "no temporary left by a signal to the process while "
	    "threads make temporaries (%d of %d rounds left some)", dirty,
	    ROUNDS);
	rounds(1, "", &killed, &dirty);
	ok(killed == ROUNDS, "in a tree: every child ended by its SIGTERM "
	    "(%d of %d)", killed, ROUNDS);
	ok(dirty == 0, "no tree left by a signal to the process while "
	    "threads make files under their final names in it (%d of %d "
	    "rounds left it)", dirty, ROUNDS);
	tl_rmtree(dir);
	return tap_done();
}
