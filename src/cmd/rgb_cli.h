/* rgb_cli.h - what dem2rgb and vgis-job's rgb steps (a plan's jobs,
 * dem2rgb --plan) share: dem2rgb's options, parsed the same way and
 * passed on to the jobs as the words given, the report, and the two
 * steps themselves. */
#ifndef TL_RGB_CLI_H
#define TL_RGB_CLI_H

#include "cli.h"
#include "rgb/rgb.h"

/* The options every job takes too (-q, -o, --dump and the plan's
 * aside). */
#define RG_CLI_OPTS "ce:f:m:t:Z:z:j:u:H:D:N:"

/* Option ch (with arg) into a: 0, or the status to exit with now (a bad
 * value: the usage error's). */
int rg_cli_option(cli *c, rg_args *a, int ch, const char *arg, tl_err *e);
/* The per-zoom report on stderr. */
void rg_cli_report(const cli *c, const rg_report *r);

/* vgis-job rgb-warp, rgb-part and rgb-gather (vgis-job(1)). */
extern const char rg_step_warp_usage[], rg_step_part_usage[],
    rg_step_gather_usage[];
int rg_step_warp(cli *c, int argc, char **argv);
int rg_step_part(cli *c, int argc, char **argv);
int rg_step_gather(cli *c, int argc, char **argv);

#endif
