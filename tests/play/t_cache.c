/* t_cache - the block cache: never more than its cap, and still serving
 * a frame; the block seen through its accessors; the renderer's state
 * handed back to its release function, once, when a block goes. */
#include "play/cache.h"
#include "fixture.h"

/* The cache never holds more than its cap, and still serves a frame. */
static void
test_cap(void)
{
	world w;
	tl_err e;
	cache *c;
	cache_stats st;
	size_t cap = 4 * 1024 * 1024; /* about five blocks */
	int served = 0;

	fx_world(&w, "bt");
	if ((c = cache_new(&w, cap, NULL, NULL, &e)) == NULL) {
		ok(0, "cache_new: %s", e.msg);
		return;
	}
	for (int f = 0; f < 60; f++) {
		pyramid_level *L = &w.ix.lev[0];
		cache_frame(c);
		/* a moving window of 3 blocks over level 0 */
		for (int k = 0; k < 3; k++) {
			int q = (f / 4 + k) % (L->blocks[0] * L->blocks[1]);
			served += cache_get(c, 0, q % L->blocks[0],
			    q / L->blocks[0]) != NULL;
		}
		cache_wait(c);
		cache_get_stats(c, &st);
		if (st.bytes > cap || st.peak > cap)
			break;
	}
	cache_get_stats(c, &st);
	ok(st.peak <= cap && st.evictions > 0 && served > 100,
	    "cache: peak %zu <= cap %zu bytes over 60 frames (%ld loads, %ld "
	    "evictions, %d of 180 asks served)", st.peak, cap, st.loads,
	    st.evictions, served);
	cache_free(c);
	world_close(&w);
}

/* The renderer's side: what it hung on blocks, counted as released. */
typedef struct {
	int released;
	size_t live;
} owner;

static void
release(void *user, void *ctx)
{
	owner *o = ctx;

	o->released++;
	o->live -= *(size_t *)user;
	free(user);
}

/* Frames until block (l, bi, bj) is in memory. */
static cblock *
fetch(cache *c, int l, int bi, int bj)
{
	cblock *b = NULL;

	for (int f = 0; f < 10 && b == NULL; f++) {
		cache_frame(c);
		if ((b = cache_get(c, l, bi, bj)) == NULL)
			cache_wait(c);
	}
	return b;
}

static void
test_owners(void)
{
	world w;
	tl_err e;
	owner o = { 0, 0 };
	cache *c;
	cblock *b;
	cache_stats s0, s1;
	size_t *user;

	fx_world(&w, "bt");
	if ((c = cache_new(&w, 64 << 20, release, &o, &e)) == NULL ||
	    (b = fetch(c, 1, 0, 1)) == NULL) {
		ok(0, "cache_new, block 1/1_0: %s", e.msg);
		return;
	}
	ok(cache_block_data(b)->level == 1 && cache_block_data(b)->bi == 0 &&
	    cache_block_data(b)->bj == 1 && cache_block_verts(b)->pos != NULL,
	    "a block as read, with its vertices");
	ok(cache_block_user(b) == NULL, "no renderer's state yet");
	user = malloc(sizeof *user);
	*user = 1000, o.live = 1000;
	cache_block_set_user(b, user);
	cache_get_stats(c, &s0);
	ok(cache_account(c, b, 1000) == 1, "the renderer's bytes fit");
	cache_get_stats(c, &s1);
	ok(s1.bytes == s0.bytes + 1000, "and are counted (%zu more)",
	    s1.bytes - s0.bytes);
	cache_block_verts_done(b);
	ok(cache_block_verts(b)->pos == NULL && cache_block_user(b) == user,
	    "the vertices go, the origin and the renderer's state stay");
	ok(cache_account(c, b, (size_t)1 << 40) == 0, "more than the cap: "
	    "no room, counted as none");
	cache_get_stats(c, &s1);
	ok(s1.bytes == s0.bytes, "back to the block's own bytes");
	cache_free(c);
	ok(o.released == 1 && o.live == 0, "cache_free hands the state to "
	    "release, once");
	world_close(&w);
}

int
main(int argc, char **argv)
{
	(void)argc;
	if (fx_init(argv[0], "t_cache") < 0)
		return 1;
	ok(fx_make("bigtujunga.tif", "bt", "") == 0,
	    "pyramid of bigtujunga.tif");
	test_cap();
	test_owners();
	fx_done();
	return tap_done();
}
