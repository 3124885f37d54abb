/* rg_scratch.c - a run's scratch directory (scratch.h), removed also when
 * SIGINT, SIGTERM or SIGHUP kills the run (rg_impl.h): the signals are
 * blocked in the caller before the directory is made (and so in every
 * thread it starts afterwards: the pool's, GDAL's warper's) and read by
 * one thread from a signalfd, which removes the directory outside any
 * handler, then lets the signal take its course (outfile.c's handler
 * removes the output's temporary, the process dies of it). A SIGKILLed
 * run's directory is the next run's sweep (scratch_begin). */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <string.h>
#include <sys/signalfd.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/outfile.h"
#include "rgb/rg_impl.h"

static void *
watch(void *arg)
{
	rg_scratch *s = arg;
	struct pollfd p[2] = { { s->sfd, POLLIN, 0 },
	    { s->quit[0], POLLIN, 0 } };
	struct signalfd_siginfo si;
	struct stat st;
	sigset_t one;

	for (;;) {
		if (poll(p, 2, -1) < 0 && errno != EINTR)
			return NULL;
		if (p[1].revents != 0)
			return NULL; /* the run is over */
		if (p[0].revents != 0 &&
		    read(s->sfd, &si, sizeof si) == sizeof si)
			break;
	}
	/* the other threads may be making a file there meanwhile */
	for (int k = 0; k < 4 && lstat(s->path, &st) == 0; k++)
		tl_rmtree(s->path);
	sigemptyset(&one);
	sigaddset(&one, (int)si.ssi_signo);
	/* the handler (outfile.c) runs here, once no output temporary
	 * is half made */
	pthread_sigmask(SIG_UNBLOCK, &one, NULL);
	raise((int)si.ssi_signo);
	return NULL; /* caught, and survived: the run goes on unguarded */
}

int
rg_scratch_begin(rg_scratch *s, tl_err *e)
{
	sigset_t set;
	int r;

	memset(s, 0, sizeof *s);
	s->sc.lock = s->sfd = s->quit[0] = s->quit[1] = -1;
	sigemptyset(&set);
	sigaddset(&set, SIGINT), sigaddset(&set, SIGTERM);
	sigaddset(&set, SIGHUP);
	pthread_sigmask(SIG_BLOCK, &set, &s->old);
	s->blocked = 1;
	if (scratch_begin(&s->sc, "dem2rgb", e) < 0) {
		rg_scratch_end(s);
		return -1;
	}
	memcpy(s->path, s->sc.path, sizeof s->path);
	if ((s->sfd = signalfd(-1, &set, SFD_CLOEXEC)) < 0 ||
	    pipe2(s->quit, O_CLOEXEC) < 0) {
		tl_failsys(e, "signalfd");
		rg_scratch_end(s);
		return -1;
	}
	if ((r = pthread_create(&s->t, NULL, watch, s)) != 0) {
		errno = r;
		tl_failsys(e, "pthread_create");
		rg_scratch_end(s);
		return -1;
	}
	s->running = 1;
	return 0;
}

void
rg_scratch_end(rg_scratch *s)
{
	/* removed first: a signal meanwhile finds it gone or going */
	scratch_end(&s->sc);
	if (s->running) {
		while (write(s->quit[1], "", 1) < 0 && errno == EINTR)
			;
		pthread_join(s->t, NULL);
	}
	s->running = 0;
	if (s->sfd >= 0)
		close(s->sfd);
	if (s->quit[0] >= 0)
		close(s->quit[0]), close(s->quit[1]);
	s->sfd = s->quit[0] = s->quit[1] = -1;
	/* one that came after the thread stopped: delivered now, as it
	 * would have been without the guard */
	if (s->blocked)
		pthread_sigmask(SIG_SETMASK, &s->old, NULL);
	s->blocked = 0;
}
