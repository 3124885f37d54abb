/* t_pmtiles - the PMTiles writer (rgb/pmtiles.h): Hilbert tile ids
 * against the specification's table and a brute-force inverse, varints,
 * a directory of known entries byte for byte, the root/leaf split read
 * back by a decoder of the test's own, and whole archives: every tile
 * read back, dedup and run counts, byte-identical for any order of the
 * calls and from four threads, and each refusal leaving nothing. */
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/gzip.h"
#include "rgb/pm_impl.h"
#include "tap.h"
#include "tmpdir.h"

/* --- Hilbert ids --------------------------------------------------- */

static void
test_hilbert(void)
{
	/* spec 4.1's table */
	static const struct { int z; uint32_t x, y; uint64_t id; } tab[] = {
		{ 0, 0, 0, 0 }, { 1, 0, 0, 1 }, { 1, 0, 1, 2 }, { 1, 1, 1, 3 },
		{ 1, 1, 0, 4 }, { 2, 0, 0, 5 }, { 12, 3423, 1763, 19078479 },
	};
	int bad = 0, badinv = 0, badadj = 0, z;
	uint32_t x, y;

	for (size_t k = 0; k < sizeof tab / sizeof tab[0]; k++) {
		uint64_t id = pm_tileid(tab[k].z, tab[k].x, tab[k].y);
		ok(id == tab[k].id, "tile id of %d/%u/%u = %llu (spec: %llu)",
		    tab[k].z, tab[k].x, tab[k].y, (unsigned long long)id,
		    (unsigned long long)tab[k].id);
	}
	/* brute force: zooms 0..7, every tile; the ids of a zoom are
	 * exactly the 4^z after the zooms above it, the inverse returns
	 * the tile, and consecutive ids are neighbouring tiles (a
	 * Hilbert curve) */
	for (int zz = 0; zz <= 7; zz++) {
		uint64_t base = ((UINT64_C(1) << 2 * zz) - 1) / 3;
		uint32_t n = 1u << zz;
		uint32_t *tx = calloc((size_t)n * n, 4), *ty = calloc((size_t)n * n, 4);
		unsigned char *seen = calloc((size_t)n * n, 1);

		for (uint32_t xx = 0; xx < n; xx++)
			for (uint32_t yy = 0; yy < n; yy++) {
				uint64_t id = pm_tileid(zz, xx, yy);
				if (id < base || id - base >= (uint64_t)n * n ||
				    seen[id - base]++) {
					bad++;
					continue;
				}
				tx[id - base] = xx, ty[id - base] = yy;
				if (pm_tile_zxy(id, &z, &x, &y) != 0 ||
				    z != zz || x != xx || y != yy)
					badinv++;
			}
		for (uint64_t k = 1; k < (uint64_t)n * n; k++) {
			long dx = labs((long)tx[k] - (long)tx[k - 1]);
			long dy = labs((long)ty[k] - (long)ty[k - 1]);
			badadj += dx + dy != 1;
		}
		free(tx), free(ty), free(seen);
	}
	ok(bad == 0, "zooms 0..7: each zoom's ids are exactly its 4^z, once "
	    "each (%d wrong)", bad);
	ok(badinv == 0, "zooms 0..7: pm_tile_zxy inverts pm_tileid (%d wrong)",
	    badinv);
	ok(badadj == 0, "zooms 0..7: consecutive ids are neighbouring tiles "
	    "(%d not)", badadj);
	/* the deepest zoom: its corners and the ids around it */
	{
		uint32_t m = 0x7fffffffu, c[4][2] = { { 0, 0 }, { m, 0 },
		    { 0, m }, { m, m } };
		int good = 1;
		for (int k = 0; k < 4; k++) {
			uint64_t id = pm_tileid(31, c[k][0], c[k][1]);
			good &= pm_tile_zxy(id, &z, &x, &y) == 0 && z == 31 &&
			    x == c[k][0] && y == c[k][1];
		}
		ok(good, "zoom 31: the corners round-trip");
	}
	ok(pm_tile_zxy(UINT64_MAX / 3 - 1, &z, &x, &y) == 0 && z == 31,
	    "the last id is of zoom 31");
	ok(pm_tile_zxy(UINT64_MAX / 3, &z, &x, &y) == -1,
	    "an id past zoom 31 is refused");
}

/* --- varints and directories --------------------------------------- */

static void
test_varint(void)
{
	static const uint64_t v[] = { 0, 1, 127, 128, 300, 16383, 16384,
	    UINT32_MAX, UINT64_C(1) << 35, UINT64_C(1) << 63, UINT64_MAX };
	static const size_t len[] = { 1, 1, 1, 2, 2, 2, 3, 5, 6, 10, 10 };
	unsigned char b[16];
	uint64_t got;
	int good = 1;

	for (size_t k = 0; k < sizeof v / sizeof v[0]; k++) {
		size_t n = pm_varint_put(b, v[k]);
		good &= n == len[k] && pm_varint_get(b, n, &got) == n &&
		    got == v[k] && pm_varint_get(b, n - 1, &got) == 0;
	}
	ok(good, "varints: 11 values round-trip in 1 to 10 bytes; cut short, "
	    "refused");
	pm_varint_put(b, 300);
	ok(b[0] == 0xac && b[1] == 0x02, "300 is ac 02 (protobuf's example)");
	memset(b, 0x80, sizeof b);
	ok(pm_varint_get(b, sizeof b, &got) == 0, "a varint of 11 bytes is "
	    "refused");
}

/* An encoded directory, decoded by the test (spec A.2): n entries. */
static pm_entry *
decode(const unsigned char *p, size_t n, size_t *count)
{
	uint64_t v, num, last = 0;
	size_t at = 0, k;
	pm_entry *en;

	if ((k = pm_varint_get(p, n, &num)) == 0 || num > n)
		return NULL;
	at = k;
	en = calloc(num ? num : 1, sizeof *en);
	for (int c = 0; c < 4; c++)
		for (size_t i = 0; i < num; i++) {
			if ((k = pm_varint_get(p + at, n - at, &v)) == 0) {
				free(en);
				return NULL;
			}
			at += k;
			if (c == 0)
				en[i].id = last += v;
			else if (c == 1)
				en[i].run = (uint32_t)v;
			else if (c == 2)
				en[i].len = (uint32_t)v;
			else
				en[i].off = v == 0 && i > 0 ?
				    en[i - 1].off + en[i - 1].len : v - 1;
		}
	*count = at == n ? num : (size_t)-1;
	return en;
}

static pm_entry *
gdecode(const unsigned char *p, size_t n, size_t *count)
{
	unsigned char *raw;
	size_t nraw;
	tl_err e;
	pm_entry *en;

	if (tl_gunzip(p, n, 1 << 28, &raw, &nraw, &e) < 0)
		return NULL;
	en = decode(raw, nraw, count);
	free(raw);
	return en;
}

static void
test_directory(void)
{
	/* contiguous, a run, a duplicate pointing back, a gap */
	static const pm_entry en[] = { { 5, 0, 42, 1 }, { 6, 42, 10, 2 },
	    { 42, 0, 42, 1 }, { 69, 52, 7, 1 } };
	static const unsigned char want[] = { 4, 5, 1, 36, 27, 1, 2, 1, 1,
	    42, 10, 42, 7, 1, 0, 1, 53 };
	pm_buf raw = { 0 }, z = { 0 };
	size_t end, n;
	tl_err e;
	pm_entry *back = NULL;

	ok(pm_dir_raw(pm_array_next, en, 0, 4, &raw, &end, &e) == 0 &&
	    end == 4 && raw.n == sizeof want &&
	    memcmp(raw.p, want, sizeof want) == 0,
	    "a directory of 4 known entries: the spec's encoding, byte for byte");
	ok(pm_dir_encode(pm_array_next, en, 0, 4, &z, NULL, &e) == 0 &&
	    (back = gdecode(z.p, z.n, &n)) != NULL && n == 4 &&
	    memcmp(back, en, sizeof en) == 0, "gzip'd, it decodes to them");
	free(back);
	pm_buf_free(&raw), pm_buf_free(&z);
}

/* count entries: ids with gaps, lengths that vary */
static pm_entry *
synthetic(size_t count)
{
	pm_entry *en = calloc(count, sizeof *en);
	unsigned s = 7;
	uint64_t id = 3, off = 0;

	for (size_t i = 0; i < count; i++) {
		s = s * 1103515245u + 12345u;
		en[i].id = id, en[i].off = off;
		en[i].len = 100 + (s >> 16) % 5000, en[i].run = 1 + (s >> 8) % 2;
		id += en[i].run + (s >> 4) % 3, off += en[i].len;
	}
	return en;
}

/* pm_dirs on count entries, read back: the root, then every leaf. */
static void
check_dirs(size_t count, int want_leaves)
{
	pm_entry *en = synthetic(count), *root, *leaf, *all = NULL;
	pm_buf r = { 0 }, l = { 0 };
	size_t nl = 0, nr = 0, got = 0, n;
	uint64_t at = 0;
	int good = 1;
	tl_err e;

	ok(pm_dirs(pm_array_next, en, count, &r, &l, &nl, &e) == 0,
	    "pm_dirs: %zu entries", count);
	ok(r.n <= PM_ROOT_MAX && (nl > 0) == want_leaves, "%zu entries: root "
	    "%zu bytes <= %d, %zu leaves", count, r.n, PM_ROOT_MAX, nl);
	root = gdecode(r.p, r.n, &nr);
	if (nl == 0) {
		all = root, got = nr;
	} else {
		all = calloc(count, sizeof *all);
		good = root != NULL && nr == nl;
		for (size_t k = 0; good && k < nr; k++) {
			good = root[k].run == 0 && root[k].off == at &&
			    root[k].off + root[k].len <= l.n;
			leaf = good ? gdecode(l.p + root[k].off, root[k].len,
			    &n) : NULL;
			good = leaf != NULL && n != (size_t)-1 &&
			    got + n <= count && leaf[0].id == root[k].id;
			if (good)
				memcpy(all + got, leaf, n * sizeof *leaf);
			got += good ? n : 0, at += root[k].len;
			free(leaf);
		}
		good = good && at == l.n;
		free(root);
	}
	ok(good && got == count && memcmp(all, en, count * sizeof *en) == 0,
	    "%zu entries read back through %s", count, nl ? "root and leaves" :
	    "the root");
	free(all), free(en);
	pm_buf_free(&r), pm_buf_free(&l);
}

/* --- whole archives ------------------------------------------------ */

#define ZMAX 6
#define SEA 0 /* the class of the 16x16 tiles of zoom 6 in a corner: a run */
#define DUP 1 /* of one tile in 11 elsewhere: duplicates, no runs */

static int
class_of(int z, uint32_t x, uint32_t y)
{
	if (z == ZMAX && x < 16 && y < 16)
		return SEA;
	if ((x * 7 + y) % 11 == 0 && z > 1)
		return DUP;
	return 2;
}

/* Tile z/x/y's bytes into b (room for 1024): their number. */
static size_t
content(int z, uint32_t x, uint32_t y, unsigned char *b)
{
	int c = class_of(z, x, y);
	unsigned s = (unsigned)pm_tileid(z, x, y) * 2654435761u;
	size_t n = c == SEA ? 300 : c == DUP ? 77 : 1 + s % 700;

	for (size_t i = 0; i < n; i++) {
		s = s * 1103515245u + 12345u;
		b[i] = c == SEA ? 's' : c == DUP ? 'd' : (unsigned char)(s >> 16);
	}
	return n;
}

typedef struct { int z; uint32_t x, y; } zxy;

static zxy *
all_tiles(size_t *n)
{
	zxy *t = calloc(((size_t)1 << 2 * (ZMAX + 1)) / 3 + 1, sizeof *t);

	*n = 0;
	for (int z = 0; z <= ZMAX; z++)
		for (uint32_t x = 0; x < 1u << z; x++)
			for (uint32_t y = 0; y < 1u << z; y++)
				t[(*n)++] = (zxy){ z, x, y };
	return t;
}

static const char *META = "{\"encoding\":\"terrarium\",\"name\":\"t\"}";

static pm_meta
meta(void)
{
	pm_meta m = { PM_PNG, 0, ZMAX, { -180, -85.0511287798, 180,
	    85.0511287798 }, { 2.35, 48.85 }, 3, NULL };

	m.json = META;
	return m;
}

struct job {
	pm_writer *w;
	const zxy *t;
	size_t n, k, step;
	int r;
};

static void *
add_some(void *arg)
{
	struct job *j = arg;
	unsigned char b[1024];
	tl_err e;

	for (size_t i = j->k; i < j->n && j->r == 0; i += j->step)
		j->r = pm_add(j->w, j->t[i].z, j->t[i].x, j->t[i].y, b,
		    content(j->t[i].z, j->t[i].x, j->t[i].y, b), &e);
	return NULL;
}

/* The archive of t[0..n) in that order on `threads` threads. */
static int
pack(const char *path, const zxy *t, size_t n, int threads)
{
	pm_meta m = meta();
	pm_writer *w;
	pthread_t th[4];
	struct job j[4];
	tl_err e;
	int r = 0;

	if ((w = pm_open(path, &e)) == NULL)
		return -1;
	for (int k = 0; k < threads; k++) {
		j[k] = (struct job){ w, t, n, (size_t)k, (size_t)threads, 0 };
		pthread_create(&th[k], NULL, add_some, &j[k]);
	}
	for (int k = 0; k < threads; k++) {
		pthread_join(th[k], NULL);
		r |= j[k].r;
	}
	if (r != 0) {
		pm_abort(w);
		return -1;
	}
	return pm_close(w, &m, &e);
}

static unsigned char *
slurp(const char *path, size_t *n)
{
	FILE *f = fopen(path, "rb");
	unsigned char *b = NULL;
	long k;

	if (f == NULL)
		return NULL;
	if (fseek(f, 0, SEEK_END) == 0 && (k = ftell(f)) > 0 &&
	    fseek(f, 0, SEEK_SET) == 0 && (b = malloc((size_t)k)) != NULL &&
	    fread(b, 1, (size_t)k, f) != (size_t)k) {
		free(b);
		b = NULL;
	}
	*n = b ? (size_t)k : 0;
	fclose(f);
	return b;
}

static uint64_t
u64(const unsigned char *p)
{
	uint64_t v = 0;

	for (int i = 7; i >= 0; i--)
		v = v << 8 | p[i];
	return v;
}

/* Every tile entry of the archive a[0..n), through root and leaves. */
static pm_entry *
entries_of(const unsigned char *a, size_t n, size_t *count, size_t *leaves)
{
	size_t nr, k, got = 0, m;
	pm_entry *root = gdecode(a + u64(a + 8), u64(a + 16), &nr), *all, *l;

	*leaves = 0;
	if (root == NULL || nr == (size_t)-1)
		return NULL;
	all = calloc(u64(a + 80) + 1, sizeof *all);
	for (k = 0; k < nr; k++) {
		if (root[k].run > 0) {
			all[got++] = root[k];
			continue;
		}
		++*leaves;
		l = gdecode(a + u64(a + 40) + root[k].off, root[k].len, &m);
		if (l == NULL || m == (size_t)-1 || got + m > u64(a + 80))
			break;
		memcpy(all + got, l, m * sizeof *l);
		got += m;
		free(l);
	}
	free(root);
	*count = got;
	return k == nr ? all : NULL;
}

static const pm_entry *
find(const pm_entry *en, size_t n, uint64_t id)
{
	size_t lo = 0, hi = n;

	while (hi - lo > 1) {	/* the last entry whose id is <= id */
		size_t mid = (lo + hi) / 2;
		if (en[mid].id <= id)
			lo = mid;
		else
			hi = mid;
	}
	return n > 0 && en[lo].id <= id && id - en[lo].id < en[lo].run ?
	    &en[lo] : NULL;
}

static int
by_u64(const void *a, const void *b)
{
	uint64_t i = *(const uint64_t *)a, j = *(const uint64_t *)b;

	return (i > j) - (i < j);
}

/* The entries and contents the archive of t[0..n) must have: ids (with
 * the class in the low 2 bits' place above them) sorted, runs counted. */
static void
expect(const zxy *t, size_t n, uint64_t *entries, uint64_t *contents)
{
	uint64_t *k = calloc(n, sizeof *k);
	int sea = 0, dup = 0;

	*entries = *contents = 0;
	for (size_t i = 0; i < n; i++) {
		int c = class_of(t[i].z, t[i].x, t[i].y);
		k[i] = pm_tileid(t[i].z, t[i].x, t[i].y) << 2 | (uint64_t)c;
		sea |= c == SEA, dup |= c == DUP;
		*contents += c == 2;
	}
	*contents += (uint64_t)sea + (uint64_t)dup;
	qsort(k, n, sizeof *k, by_u64);
	for (size_t i = 0; i < n; i++)
		*entries += !(i > 0 && (k[i] >> 2) == (k[i - 1] >> 2) + 1 &&
		    (k[i] & 3) == (k[i - 1] & 3) && (k[i] & 3) != 2);
	free(k);
}

static int
pos_is(const unsigned char *p, double lon, double lat)
{
	int32_t a = (int32_t)(uint32_t)(p[0] | p[1] << 8 | p[2] << 16 |
	    (uint32_t)p[3] << 24);
	int32_t b = (int32_t)(uint32_t)(p[4] | p[5] << 8 | p[6] << 16 |
	    (uint32_t)p[7] << 24);

	return fabs(a / 1e7 - lon) <= 0.6e-7 && fabs(b / 1e7 - lat) <= 0.6e-7;
}

static void
check_archive(const char *path, const zxy *t, size_t n)
{
	size_t an, count = 0, leaves, bad = 0;
	unsigned char *a = slurp(path, &an), b[1024], *mj = NULL;
	uint64_t entries, contents;
	pm_entry *en;
	pm_meta m = meta();
	size_t nm = 0;
	tl_err e;

	if (!ok(a != NULL && an > PM_HEADER, "%s read", path))
		return;
	expect(t, n, &entries, &contents);
	ok(memcmp(a, "PMTiles\3", 8) == 0 && a[96] == 1 && a[97] == 2 &&
	    a[98] == 1 && a[99] == PM_PNG && a[100] == 0 && a[101] == ZMAX &&
	    a[118] == 3, "header: PMTiles v3, clustered, gzip'd directories, "
	    "tiles as given, PNG, zooms 0..%d, centre zoom 3", ZMAX);
	ok(pos_is(a + 102, m.bounds[0], m.bounds[1]) &&
	    pos_is(a + 110, m.bounds[2], m.bounds[3]) &&
	    pos_is(a + 119, m.center[0], m.center[1]),
	    "header: bounds and centre to 10^-7 degree");
	ok(u64(a + 72) == n && u64(a + 80) == entries &&
	    u64(a + 88) == contents, "header: %zu tiles, %llu entries, %llu "
	    "contents (%llu, %llu, %llu)", n, (unsigned long long)entries,
	    (unsigned long long)contents, (unsigned long long)u64(a + 72),
	    (unsigned long long)u64(a + 80), (unsigned long long)u64(a + 88));
	ok(u64(a + 8) == PM_HEADER && u64(a + 24) == u64(a + 8) + u64(a + 16) &&
	    u64(a + 40) == u64(a + 24) + u64(a + 32) &&
	    u64(a + 56) == u64(a + 40) + u64(a + 48) &&
	    u64(a + 56) + u64(a + 64) == an && u64(a + 8) + u64(a + 16) <= 16384,
	    "sections in the spec's order, end to end; root in the first 16 KiB");
	ok(tl_gunzip(a + u64(a + 24), u64(a + 32), 1 << 20, &mj, &nm, &e) == 0 &&
	    nm == strlen(META) && memcmp(mj, META, nm) == 0,
	    "the metadata, gzip'd, as given");
	free(mj);
	en = entries_of(a, an, &count, &leaves);
	ok(en != NULL && count == entries, "directories: %zu tile entries "
	    "through %zu leaves", count, leaves);
	for (size_t i = 0; en != NULL && i < n; i++) {
		const pm_entry *f = find(en, count,
		    pm_tileid(t[i].z, t[i].x, t[i].y));
		size_t k = content(t[i].z, t[i].x, t[i].y, b);
		bad += f == NULL || f->len != k || u64(a + 56) + f->off + k >
		    an || memcmp(a + u64(a + 56) + f->off, b, k) != 0;
	}
	ok(en != NULL && bad == 0, "every one of %zu tiles read back, byte for "
	    "byte (%zu wrong)", n, bad);
	free(en), free(a);
}

static int
same_file(const char *p, const char *q)
{
	size_t n, m;
	unsigned char *a = slurp(p, &n), *b = slurp(q, &m);
	int r = a != NULL && b != NULL && n == m && memcmp(a, b, n) == 0;

	free(a), free(b);
	return r;
}

static void
test_archives(const char *dir)
{
	size_t n;
	zxy *t = all_tiles(&n), *r = calloc(n, sizeof *r);
	const char *a = tmpdir_join(dir, "a.pmtiles");
	const char *b = tmpdir_join(dir, "b.pmtiles");
	const char *c = tmpdir_join(dir, "c.pmtiles");
	unsigned s = 11;

	/* b: reversed then shuffled */
	for (size_t i = 0; i < n; i++)
		r[i] = t[n - 1 - i];
	for (size_t i = n - 1; i > 0; i--) {
		size_t j;
		zxy x;
		s = s * 1103515245u + 12345u;
		j = (s >> 8) % (i + 1);
		x = r[i], r[i] = r[j], r[j] = x;
	}
	ok(pack(a, t, n, 1) == 0, "zooms 0..%d, %zu tiles, in zoom order", ZMAX,
	    n);
	check_archive(a, t, n);
	ok(pack(b, r, n, 1) == 0 && same_file(a, b),
	    "shuffled: byte-identical");
	ok(pack(c, r, n, 4) == 0 && same_file(a, c),
	    "shuffled on 4 threads at once: byte-identical");
	ok(tmpdir_entries(dir, "") == 3, "the 3 archives, no temporary left");
	/* one tile */
	{
		pm_meta m = meta();
		tl_err e;
		pm_writer *w = pm_open(c, &e);
		m.minzoom = m.maxzoom = m.center_zoom = 5;
		unsigned char *p;
		ok(w != NULL && pm_add(w, 5, 3, 4, "x", 1, &e) == 0 &&
		    pm_close(w, &m, &e) == 0, "an archive of one tile");
		p = slurp(c, &n);
		ok(p != NULL && u64(p + 72) == 1 && u64(p + 80) == 1 &&
		    u64(p + 88) == 1 && u64(p + 48) == 0 && p[100] == 5 &&
		    p[101] == 5 && u64(p + 64) == 1 && p[n - 1] == 'x',
		    "one tile: its counts, zooms and byte");
		free(p);
	}
	free(t), free(r);
}

/* A writer refused at close, or at an add: nothing left in dir. */
static void
refused(const char *dir, const char *what, const char *want, int z,
    uint32_t x, uint32_t y, size_t n, pm_meta m, int twice)
{
	const char *path = tmpdir_join(dir, "r.pmtiles");
	pm_writer *w;
	tl_err e = { "" };
	int r = 0;

	if ((w = pm_open(path, &e)) == NULL) {
		ok(0, "%s: pm_open: %s", what, e.msg);
		return;
	}
	/* z < 0: no tile */
	if (z >= 0 && (r = pm_add(w, z, x, y, "tile", n, &e)) == 0 && twice)
		r = pm_add(w, z, x, y, "other", 5, &e);
	r = r == 0 ? pm_close(w, &m, &e) : (pm_abort(w), -1);
	ok(r == -1 && strstr(e.msg, want) != NULL && strstr(e.msg, "r.pmtiles"),
	    "%s: refused (%s)", what, e.msg);
	ok(tmpdir_entries(dir, "") == 0, "%s: nothing left", what);
}

static void
test_refusals(void)
{
	char dir[PATH_MAX];
	pm_meta m = meta(), bad;
	tl_err e;
	pm_writer *w;

	if (tmpdir_make(dir, sizeof dir, "t_pmtiles_r") != 0)
		return;
	refused(dir, "zoom 32", "zoom not in", 32, 0, 0, 4, m, 0);
	refused(dir, "x past 2^z", "past 2^3", 3, 8, 0, 4, m, 0);
	refused(dir, "y past 2^z", "past 2^0", 0, 0, 1, 4, m, 0);
	refused(dir, "an empty tile", "empty", 2, 1, 1, 0, m, 0);
	refused(dir, "a tile given twice", "2/1/3 given twice", 2, 1, 3, 4, m,
	    1);
	refused(dir, "no tile", "no tile", -1, 0, 0, 0, m, 0);
	bad = m, bad.minzoom = 3;
	refused(dir, "a tile above minzoom", "not within", 2, 1, 0, 4, bad, 0);
	bad = m, bad.maxzoom = 4, bad.center_zoom = 2;
	refused(dir, "a tile past maxzoom", "not within", 5, 0, 0, 4, bad, 0);
	bad = m, bad.json = "[1]";
	refused(dir, "metadata an array", "not a JSON object", 1, 0, 0, 4, bad,
	    0);
	bad = m, bad.json = "{\"a\":";
	refused(dir, "metadata cut short", "metadata:", 1, 0, 0, 4, bad, 0);
	bad = m, bad.json = "{\"a\":1,\"a\":2}";
	refused(dir, "metadata with a key twice", "metadata:", 1, 0, 0, 4, bad,
	    0);
	bad = m, bad.bounds[3] = 91;
	refused(dir, "north at 91", "bounds", 1, 0, 0, 4, bad, 0);
	bad = m, bad.type = 1;
	refused(dir, "a vector tile type", "tile type", 1, 0, 0, 4, bad, 0);
	bad = m, bad.center_zoom = 9;
	refused(dir, "centre zoom past maxzoom", "centre", 1, 0, 0, 4, bad, 0);
	w = pm_open(tmpdir_join(dir, "r.pmtiles"), &e);
	ok(w != NULL && pm_add(w, 1, 1, 1, "t", 1, &e) == 0,
	    "a writer with a tile");
	pm_abort(w);
	ok(tmpdir_entries(dir, "") == 0, "pm_abort: nothing left");
	ok(pm_open(tmpdir_join(dir, "no/such/r.pmtiles"), &e) == NULL &&
	    strstr(e.msg, "no/such/r.pmtiles") != NULL,
	    "pm_open in a missing directory: refused at once (%s)", e.msg);
	tmpdir_done(dir);
}

int
main(void)
{
	char dir[PATH_MAX];

	test_hilbert();
	test_varint();
	test_directory();
	check_dirs(1000, 0);
	check_dirs(15000, 1);	/* fewer than 16384, but too big for the root */
	check_dirs(200000, 1);
	if (ok(tmpdir_make(dir, sizeof dir, "t_pmtiles") == 0, "a scratch "
	    "directory")) {
		test_archives(dir);
		tmpdir_done(dir);
	}
	test_refusals();
	return tap_done();
}
