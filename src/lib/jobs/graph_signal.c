/* graph_signal.c - the signal that asks the supervisor to stop (graph.h,
 * graph_signal): its handler, installed by graph_run, and the one piece
 * of process state it sets. A leaf: graph.c and graph_wait.c read it. */
#include <signal.h>

#include "jobs/graph_impl.h"

/* set by the handler (a handler can reach nothing else) */
static volatile sig_atomic_t stop_signal;

static void
on_signal(int sig)
{
	stop_signal = sig;
}

void
graph_catch_signals(void)
{
	struct sigaction sa = { .sa_handler = on_signal };
	const int sigs[3] = { SIGINT, SIGTERM, SIGHUP };

	/* installed for good: a signal between two graphs must still stop
	 * the next one and reach the caller */
	sigemptyset(&sa.sa_mask);
	for (int i = 0; i < 3; i++)
		sigaction(sigs[i], &sa, NULL);
}

int
graph_signal(void)
{
	return stop_signal;
}
