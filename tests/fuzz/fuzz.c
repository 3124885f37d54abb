/* fuzz.c - the fuzz targets' input files (fuzz.h). */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fuzz.h"

/* The fuzz process's private directory: made once, kept for its life
 * (a target runs millions of inputs; each replaces the last file). */
static const char *
dir(void)
{
	static char d[256];

	if (d[0] == '\0') {
		const char *t = getenv("TMPDIR");
		snprintf(d, sizeof d, "%s/tlfuzz.XXXXXX", t && *t ? t : "/tmp");
		if (mkdtemp(d) == NULL)
			abort();
	}
	return d;
}

const char *
fuzz_file(const char *name, const uint8_t *data, size_t size)
{
	static char path[512];
	int fd;

	snprintf(path, sizeof path, "%s/%s", dir(), name);
	if ((fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600)) < 0)
		return NULL;
	while (size > 0) {
		ssize_t w = write(fd, data, size);
		if (w <= 0) {
			close(fd);
			return NULL;
		}
		data += w, size -= (size_t)w;
	}
	close(fd);
	return path;
}
