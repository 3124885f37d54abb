/* t_outfile_signal - a fatal signal sent to a process whose threads are
 * making temporaries (outfile.h) leaves none behind, whichever thread
 * the kernel hands the signal to: the handler waits for the temporaries
 * under way to be registered. Each round forks a child whose worker
 * threads make and abort temporaries in a loop while its main thread
 * waits (so the signal usually lands there, not in a maker), and kills
 * it with SIGTERM after a random delay; then the directory must be
 * empty. Before the wait, 46 rounds of 60 left a temporary; with the
 * wait but the handler installed only with the first output, 1 to 7
 * (the default action met a thread inside the call making its first). */
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

/* The child: makers until the signal ends it. */
static void
child(void)
{
	pthread_t t[MAKERS];

	tl_out_catch(); /* as every program's cli_init does */
	for (long k = 0; k < MAKERS; k++)
		pthread_create(&t[k], NULL, maker, (void *)k);
	pthread_join(t[0], NULL);
	_exit(0);
}

int
main(void)
{
	int dirty = 0, killed = 0;

	snprintf(dir, sizeof dir, "%s/t_outfile_signal.XXXXXX",
	    getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (mkdtemp(dir) == NULL)
		return 2;
	srand(7);
	for (int r = 0; r < ROUNDS; r++) {
		struct timespec ts = { 0, 2000000 + rand() % 3000000 };
		int st;
		pid_t pid = fork();
		if (pid == 0)
			child();
		nanosleep(&ts, NULL);
		kill(pid, SIGTERM);
		waitpid(pid, &st, 0);
		killed += WIFSIGNALED(st) && WTERMSIG(st) == SIGTERM;
		if (tmpdir_entries(dir, ".f") != 0) {
			dirty++;
			tl_rmtree(dir);
			mkdir(dir, 0700);
		}
	}
	ok(killed == ROUNDS, "every child ended by its SIGTERM (%d of %d)",
	    killed, ROUNDS);
	ok(dirty == 0, "no temporary left by a signal to the process while "
	    "threads make temporaries (%d of %d rounds left some)", dirty,
	    ROUNDS);
	tl_rmtree(dir);
	return tap_done();
}
