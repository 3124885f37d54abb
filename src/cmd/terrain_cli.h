/* terrain_cli.h - what vgis2terrain and vgis-job's terrain steps (a
 * plan's jobs, vgis2terrain --plan) share: the export's options, parsed
 * the same way and passed on to the jobs as the same words, the report,
 * and the two steps themselves. */
#ifndef TL_TERRAIN_CLI_H
#define TL_TERRAIN_CLI_H

#include "cli.h"
#include "terrain/terrain.h"

/* The export's options: getopt letters and the long ones' values. */
#define TR_CLI_OPTS "f:j:qz"
enum { TR_CLI_PARENT = 'P', TR_CLI_ATTRIB = 'A' };
#define TR_CLI_LONGOPTS \
	{ "parent-url", required_argument, NULL, TR_CLI_PARENT }, \
	{ "attribution", required_argument, NULL, TR_CLI_ATTRIB }

/* Option ch (with optarg) into a: 1 taken, 0 not an export option, -1 a
 * bad value (the caller's usage error). -j sets a->jobs. */
int tr_cli_option(cli *c, int ch, tr_args *a);
/* The export's options of a as words for a plan's jobs (-j aside), into
 * w (at most 8); their count. */
int tr_cli_words(const tr_args *a, const char **w);
/* The per-level report on stderr. */
void tr_cli_report(const cli *c, const tr_report *r);

/* vgis-job terrain-part and terrain-gather (vgis-job(1)). */
extern const char tr_step_part_usage[], tr_step_gather_usage[];
int tr_step_part(cli *c, int argc, char **argv);
int tr_step_gather(cli *c, int argc, char **argv);

#endif
