/* t_gl_text - text over a frame: white glyphs with a shadow on a dark
 * band at the top left, nothing else touched. */
#include "play/gl_text.h"
#include "fixture.h"

#define W 320
#define H 200

static void
test_draw(gl_text *t, gl_ctx *g)
{
	static unsigned char rgb[W * H * 3];
	int white = 0, dark = 0, untouched = 1;

	glViewport(0, 0, W, H);
	glClearColor(0.5f, 0.5f, 0.5f, 1);
	glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
	gl_text_draw(t, W, H, "tileplay\nsecond line");
	gl_ctx_read_rgb(g, rgb);
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			const unsigned char *p = &rgb[3 * (y * W + x)];
			if (y < 40 && x < 120) {
				white += p[0] == 255 && p[1] == 255 && p[2] == 255;
				dark += p[0] < 100;
			} else
				untouched &= p[0] >= 127 && p[0] <= 128;
		}
	ok(white > 50 && dark > 500, "glyphs (%d white pixels) on a band (%d "
	    "dark) at the top left", white, dark);
	ok(untouched && rgb[0] >= 127, "the rest of the frame untouched");
}

int
main(int argc, char **argv)
{
	gl_ctx *g;
	gl_text *t;
	tl_err e;

	(void)argc;
	if (fx_init(argv[0], "t_gl_text") < 0)
		return 1;
	if ((g = fx_headless(W, H)) != NULL) {
		ok((t = gl_text_new(&e)) != NULL, "gl_text_new");
		if (t != NULL)
			test_draw(t, g);
		gl_text_free(t);
		gl_ctx_close(g);
	}
	fx_done();
	return tap_done();
}
