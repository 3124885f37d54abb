/* fz_opts - the option parsers: the input is an argv (NUL-separated
 * words) given to the cli module with a program's own options, the
 * shared -z and DEM options (dem_option: encodings, numbers, cell sizes,
 * datums) and the filters' operands. Usage errors are printed to stderr,
 * as a program would. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "fuzz.h"

#define MAXW 24

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const char usage[] = "[-k kernel] [-m mode] [in [out]]\n";
	static const struct option longopts[] = {
		{ "kernel", required_argument, NULL, 'k' },
		{ "tau", required_argument, NULL, 't' },
		{ NULL, 0, NULL, 0 },
	};
	char buf[4096], *argv[MAXW + 2];
	const char *in, *out;
	int argc = 0, ch;
	cli c;

	if (size >= sizeof buf)
		return 0;
	memcpy(buf, data, size);
	buf[size] = '\0';
	argv[argc++] = "prog";
	for (char *p = buf; p < buf + size && argc < MAXW; p += strlen(p) + 1)
		argv[argc++] = p;
	argv[argc] = NULL;
	optind = 0; /* GNU getopt: start afresh for each input */
	cli_init(&c, argv, usage, CLI_COMPRESSION | CLI_DEM);
	while ((ch = cli_next(&c, argc, argv, "k:m:v", longopts)) != -1)
		;
	if (c.status < 0)
		(void)cli_operands(&c, argc - optind, argv + optind, &in, &out);
	return 0;
}
