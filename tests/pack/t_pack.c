/* t_pack - tilepack's work as a library (pack.h): each check on its own
 * (a vertex map's level, DEM size and georeferencing; the level count;
 * the directory it may replace), then a pyramid packed from vertex maps
 * written here that the checker (verify.h, no code in common) passes
 * against the DEM, the same for any number of jobs, and refusals that
 * leave an existing pyramid as it was and nothing else behind. */
#include <dirent.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "qem/fqm.h"
#include "pack/pack.h"
#include "pyramid/pyramid.h"
#include "verify/verify.h"
#include "tap.h"
#include "tmpdir.h"
#include "tiff.h"

#define W 200
#define H 150

static char tmp[PATH_MAX - 64];
static float dem_z[W * H];
static georef dem_geo;

static void
test_check_level(void)
{
	georef g;
	fqm_info fi = { 0 };
	tl_err e;

	geo_init_none(&g, 2, 3);
	g.width = 64, g.height = 48;
	fi.level = 0, fi.size0[0] = 64, fi.size0[1] = 48, fi.geo = g;
	ok(pack_check_level(&fi, 0, &g, "v0", &e) == 0, "a level of the "
	    "DEM in its place passes");
	ok(pack_check_level(&fi, 1, &g, "v0", &e) < 0 && strcmp(e.msg,
	    "v0: is level 0, expected level 1 (levels go in order from 0)") ==
	    0, "another level refused: %s", e.msg);
	fi.size0[0] = 65;
	ok(pack_check_level(&fi, 0, &g, "v0", &e) < 0 && strcmp(e.msg,
	    "v0: made from a 65x48 DEM, the DEM is 64x48") == 0, "another "
	    "DEM's size refused: %s", e.msg);
	fi.size0[0] = 64;
	fi.geo.cell[0] = 5;
	ok(pack_check_level(&fi, 0, &g, "v0", &e) < 0 && strcmp(e.msg,
	    "v0: georeferencing (cell) differs from the DEM's: made with "
	    "other DEM options?") == 0, "another cell refused: %s", e.msg);
	fi.geo = g, fi.geo.has_nodata = 1, fi.geo.nodata = -9999;
	ok(pack_check_level(&fi, 0, &g, "v0", &e) < 0 && strstr(e.msg,
	    "(nodata)") != NULL, "another nodata refused (geo_differs): %s",
	    e.msg);
	fi.geo = g, fi.geo.epsg = 4326;
	ok(pack_check_level(&fi, 0, &g, "v0", &e) < 0 && strstr(e.msg,
	    "(crs)") != NULL, "another CRS refused: %s", e.msg);
}

static void
test_check_count(void)
{
	tl_err e;

	ok(pack_check_count(1, 64, 48, &e) == 0 &&
	    pack_check_count(2, 200, 150, &e) == 0 &&
	    pack_check_count(5, 1197, 643, &e) == 0, "level counts: 1 for "
	    "64x48, 2 for 200x150, 5 for 1197x643");
	ok(pack_check_count(2, 64, 48, &e) < 0 && strcmp(e.msg, "2 levels "
	    "given, a 64x48 DEM's pyramid has 1 (0 .. the first that fits one "
	    "129x129 block)") == 0, "a level too many refused: %s", e.msg);
	ok(pack_check_count(4, 1197, 643, &e) < 0 && strstr(e.msg,
	    "4 levels given, a 1197x643 DEM's pyramid has 5") != NULL,
	    "a level too few refused");
}

static int
touch(const char *dir, const char *name)
{
	char p[PATH_MAX];
	FILE *f;

	snprintf(p, sizeof p, "%s/%s", dir, name);
	if ((f = fopen(p, "w")) == NULL)
		return -1;
	return fclose(f);
}

static void
test_check_dir(void)
{
	char d[PATH_MAX];
	struct stat st;
	tl_err e;

	snprintf(d, sizeof d, "%s/absent", tmp);
	ok(pack_check_dir(d, 0, &e) == 0, "an absent directory may be made");
	snprintf(d, sizeof d, "%s/file", tmp);
	ok(touch(tmp, "file") == 0 && pack_check_dir(d, 1, &e) < 0 &&
	    strstr(e.msg, "exists and is not a directory") != NULL,
	    "a file is never replaced, even forced: %s", e.msg);
	snprintf(d, sizeof d, "%s/empty", tmp);
	ok(mkdir(d, 0777) == 0 && pack_check_dir(d, 0, &e) == 0 &&
	    stat(d, &st) < 0, "an empty directory may be replaced (removed)");
	snprintf(d, sizeof d, "%s/keep", tmp);
	ok(mkdir(d, 0777) == 0 && touch(d, "precious") == 0 &&
	    pack_check_dir(d, 0, &e) < 0 && strstr(e.msg, "not a pyramid "
	    "(no index.json); use -f") != NULL, "a directory that is not a "
	    "pyramid is refused: %s", e.msg);
	ok(pack_check_dir(d, 1, &e) == 0 && touch(d, "index.json") == 0 &&
	    pack_check_dir(d, 0, &e) == 0, "... unless forced, or a pyramid");
}

/* The DEM: rolling hills, exact samples, no voids. */
static int
make_dem(char *path, size_t n)
{
	static const dem_opts none;
	tl_err e;
	dem *d;

	for (int j = 0; j < H; j++)
		for (int i = 0; i < W; i++)
			dem_z[j * W + i] = (float)(200 + 30 * sin(i * 0.05) *
			    cos(j * 0.07) + 0.2 * i + 3 * sin(i * 0.4 + j));
	snprintf(path, n, "%s/dem.tif", tmp);
	if (write_tiff(path, W, H, dem_z) < 0 ||
	    (d = dem_open(path, &none, &e)) == NULL)
		return -1;
	dem_geo = *dem_georef(d);
	dem_close(d);
	return 0;
}

/* Level l's vertex map: the DEM sub-sampled (QEM's answer is not needed
 * for a true E), zero offsets when displaced, georeferencing g. */
static int
write_vmap(const char *path, int l, int displaced, const georef *g)
{
	int w = geo_level_size(W, l), h = geo_level_size(H, l), r = -1;
	float *row = calloc((size_t)3 * w, sizeof *row);
	rs_writer *wr = NULL;
	rs_header hd;
	tl_err e;

	rs_header_init(&hd, w, h);
	if (row == NULL || rs_put_georef(g, &hd, &e) < 0 ||
	    rs_set_int(&hd, FQM_ATTR_VERSION, FQM_VERSION, &e) < 0 ||
	    rs_set_string(&hd, FQM_ATTR_KIND, "vertices", &e) < 0 ||
	    rs_set_int(&hd, FQM_ATTR_LEVEL, l, &e) < 0 ||
	    rs_set_v2i(&hd, FQM_ATTR_SIZE0, W, H, &e) < 0 ||
	    rs_set_string(&hd, FQM_ATTR_MODE, "subsample", &e) < 0 ||
	    rs_set_string(&hd, FQM_ATTR_KERNEL, l ? "binomial" : "none",
	    &e) < 0 || rs_add_channel(&hd, "Z", &e) < 0 ||
	    (displaced && (rs_add_channel(&hd, "X", &e) < 0 ||
	    rs_add_channel(&hd, "Y", &e) < 0)) ||
	    (wr = rs_create(path, &hd, RS_ZIP, &e)) == NULL)
		goto done;
	for (int j = 0; j < h; j++) {
		int J = j << l < H ? j << l : H - 1;
		float *z = row + (size_t)(displaced ? 2 : 0) * w;
		for (int i = 0; i < w; i++)
			z[i] = dem_z[J * W + (i << l < W ? i << l : W - 1)];
		if (rs_write_row(wr, row, &e) < 0)
			goto done;
	}
	r = rs_finish(wr, &e);
	wr = NULL;
done:
	if (r < 0)
		printf("# %s: %s\n", path, e.msg);
	rs_abort(wr);
	rs_header_free(&hd);
	free(row);
	return r;
}

/* pack_run on the DEM and vertex maps v[0 .. n-1] into dir. */
static int
pack(const char *dem_path, const char *dir, char **v, int n, int jobs,
    pack_level *out, tl_err *e)
{
	pack_args a = { 0 };

	a.dem_path = dem_path, a.dir = dir;
	a.levels = v, a.nlevels = n, a.jobs = jobs;
	return pack_run(&a, out, e);
}

/* The file's bytes, malloc'd; NULL if it cannot be read. */
static char *
slurp(const char *dir, const char *name)
{
	char p[PATH_MAX], *s;
	FILE *f;
	long n;

	snprintf(p, sizeof p, "%s/%s", dir, name);
	if ((f = fopen(p, "rb")) == NULL)
		return NULL;
	fseek(f, 0, SEEK_END);
	n = ftell(f);
	rewind(f);
	if ((s = calloc(1, (size_t)n + 1)) != NULL &&
	    fread(s, 1, (size_t)n, f) != (size_t)n) {
		free(s);
		s = NULL;
	}
	fclose(f);
	return s;
}

/* The pyramid passes every check of the checker against the DEM. */
static void
checked(const char *dir, const char *dem_path)
{
	vf_report r;
	tl_err e;

	if (vf_check(dir, dem_path, NULL, NULL, &r, &e) < 0) {
		ok(0, "the checker ran: %s", e.msg);
		return;
	}
	/* E exact: some selection's error reaches tau, within float32 */
	ok(r.total == 0 && r.dem && r.nlevels == 2 && r.lev[1].displaced &&
	    fabs(r.lev[1].tight - 1) < 1e-3, "the checker passes it against "
	    "the DEM (%lld violations), level 1 tightness %.6f",
	    r.total, r.lev[1].tight);
	vf_report_free(&r);
}

static void
test_report(const pack_level *out)
{
	char *buf = NULL, want[256];
	size_t n = 0;
	FILE *f = open_memstream(&buf, &n);

	if (f == NULL)
		return;
	pack_report(f, "t", out, 2);
	fclose(f);
	snprintf(want, sizeof want, "t: level 0: 200x150 vertices, 2x2 "
	    "blocks, 1D, max E %.3f m, max base error 0.000 m\nt: level 1: "
	    "101x76 vertices, 1x1 blocks, 3D, max E %.3f m, max base error "
	    "%.3f m\n", out[0].st.max_e, out[1].st.max_e,
	    out[1].st.max_base);
	ok(strcmp(buf, want) == 0, "the report: a line per level");
	free(buf);
}

static void
test_run(void)
{
	char dem_path[PATH_MAX], dir[PATH_MAX], dir1[PATH_MAX];
	char v[4][PATH_MAX], *lv[2] = { v[0], v[1] };
	char *sw[2] = { v[1], v[0] }, *other[2] = { v[0], v[2] };
	pack_level out[2];
	georef g;
	tl_err e;
	char *ix = NULL, *ix1 = NULL;
	int same = 1;

	snprintf(v[0], sizeof v[0], "%s/v0.exr", tmp);
	snprintf(v[1], sizeof v[1], "%s/v1.exr", tmp);
	snprintf(v[2], sizeof v[2], "%s/v1cell.exr", tmp);
	if (make_dem(dem_path, sizeof dem_path) < 0) {
		ok(0, "set up: the DEM");
		return;
	}
	/* level 1 displaced; its copy read with another cell size */
	g = dem_geo, g.cell[0] = 2, g.cell[1] = 2;
	if (write_vmap(v[0], 0, 0, &dem_geo) < 0 ||
	    write_vmap(v[1], 1, 1, &dem_geo) < 0 ||
	    write_vmap(v[2], 1, 1, &g) < 0) {
		ok(0, "set up: the vertex maps");
		return;
	}
	snprintf(dir, sizeof dir, "%s/p", tmp);
	mkdir(dir, 0777);
	snprintf(dir, sizeof dir, "%s/p/pyr", tmp);
	snprintf(dir1, sizeof dir1, "%s/p/pyr1", tmp);
	e.msg[0] = '\0';
	ok(pack(dem_path, dir, lv, 2, 2, out, &e) == 0, "packed with 2 jobs "
	    "%s", e.msg);
	ok(out[0].size[0] == 200 && out[0].size[1] == 150 &&
	    out[0].blocks[0] == 2 && out[0].blocks[1] == 2 &&
	    !out[0].displaced && out[1].size[0] == 101 &&
	    out[1].blocks[0] == 1 && out[1].displaced &&
	    out[0].st.max_base == 0 && out[0].st.samples == W * H &&
	    out[1].st.max_base > 0, "levels: sizes, blocks, displaced, "
	    "samples; a base error on level 1 only");
	test_report(out);
	checked(dir, dem_path);
	ok(pack(dem_path, dir1, lv, 2, 1, out, &e) == 0 &&
	    (ix = slurp(dir, "index.json")) != NULL &&
	    (ix1 = slurp(dir1, "index.json")) != NULL &&
	    strcmp(ix, ix1) == 0, "one job: the same index");
	free(ix1);
	ok(pack(dem_path, dir, lv, 1, 2, out, &e) < 0 && strstr(e.msg,
	    "1 levels given, a 200x150 DEM's pyramid has 2") != NULL,
	    "a level too few refused: %s", e.msg);
	/* both levels fail, on two threads: the lowest one's fault */
	for (int k = 0; k < 8 && same; k++)
		same = pack(dem_path, dir, sw, 2, 2, out, &e) < 0 &&
		    strstr(e.msg, "v1.exr: is level 1, expected level 0") !=
		    NULL;
	ok(same, "levels out of order refused with level 0's fault, "
	    "whatever the threads' timing (8 runs): %s", e.msg);
	ok(pack(dem_path, dir, other, 2, 2, out, &e) < 0 && strstr(e.msg,
	    "v1cell.exr: georeferencing (cell) differs") != NULL, "a level "
	    "of other DEM options refused: %s", e.msg);
	ok(ix != NULL && (ix1 = slurp(dir, "index.json")) != NULL &&
	    strcmp(ix, ix1) == 0, "refused runs leave the pyramid as it was");
	free(ix), free(ix1);
}

/* Nothing in tmp/p but the two pyramids: no temporaries left. */
static void
test_clean(void)
{
	char p[PATH_MAX];
	struct dirent *de;
	DIR *d;
	int other = 0;

	snprintf(p, sizeof p, "%s/p", tmp);
	if ((d = opendir(p)) == NULL) {
		ok(0, "%s: opened", p);
		return;
	}
	while ((de = readdir(d)) != NULL)
		other += strcmp(de->d_name, ".") != 0 &&
		    strcmp(de->d_name, "..") != 0 &&
		    strcmp(de->d_name, "pyr") != 0 &&
		    strcmp(de->d_name, "pyr1") != 0;
	closedir(d);
	ok(other == 0, "nothing else left beside the pyramids (%d)", other);
}

int
main(void)
{
	if (tmpdir_make(tmp, sizeof tmp, "tlpack") < 0) {
		ok(0, "set up");
		return tap_done();
	}
	test_check_level();
	test_check_count();
	test_check_dir();
	test_run();
	test_clean();
	tmpdir_done(tmp);
	return tap_done();
}
