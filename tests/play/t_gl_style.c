/* t_gl_style - styles and colour maps, no GL: the colour modes' names,
 * the height map's ends (viridis' first and last colours, as tileplay(1)
 * says), the error ramp blue-grey-red, the level colours. */
#include <math.h>
#include <string.h>

#include "play/gl_style.h"
#include "tap.h"

static void
test_names(void)
{
	enum gl_colour c = GL_NCOLOUR;
	int round = 1;

	for (int k = 0; k < GL_NCOLOUR; k++)
		round &= gl_style_colour_parse(gl_style_colour_name(k), &c) == 0
		    && (int)c == k;
	ok(round, "every colour mode parses back from its name");
	ok(gl_style_colour_parse("hue", &c) < 0, "another name: -1");
	ok(strcmp(gl_style_colour_name(GL_BY_ERROR), "error") == 0 &&
	    strcmp(gl_style_colour_name(GL_NCOLOUR), "?") == 0,
	    "names: error, ? past the last");
}

static void
test_defaults(void)
{
	gl_style s;

	gl_style_init(&s);
	ok(s.colour == GL_BY_HEIGHT && s.light && !s.wire && s.skirts,
	    "defaults: height, light, no wireframe, skirts");
	ok(fabsf(s.background[0] * 255 - 158) < 0.5f &&
	    fabsf(s.background[2] * 255 - 209) < 0.5f,
	    "a pale blue-grey background");
}

static void
test_height(void)
{
	unsigned char lo[3], hi[3], below[3], mid[3];

	gl_style_height_rgb(0, lo);
	gl_style_height_rgb(1, hi);
	gl_style_height_rgb(-5, below);
	gl_style_height_rgb(0.5, mid);
	ok(lo[0] == 68 && lo[1] == 1 && lo[2] == 84, "lowest: 68 1 84 (%d %d "
	    "%d)", lo[0], lo[1], lo[2]);
	ok(hi[0] == 253 && hi[1] == 231 && hi[2] == 37, "highest: 253 231 37 "
	    "(%d %d %d)", hi[0], hi[1], hi[2]);
	ok(memcmp(below, lo, 3) == 0, "clamped below");
	ok(mid[1] > mid[0] && mid[2] > mid[0], "the middle is teal (%d %d %d)",
	    mid[0], mid[1], mid[2]);
}

static void
test_ramps(void)
{
	float v[GL_STYLE_RAMP][3], e[GL_STYLE_RAMP][3];
	unsigned char lo[3];

	gl_style_ramp(GL_BY_HEIGHT, v);
	gl_style_ramp(GL_BY_ERROR, e);
	gl_style_height_rgb(0, lo);
	ok(lrintf(v[0][0] * 255) == lo[0] && lrintf(v[0][2] * 255) == lo[2],
	    "the height ramp is the height map's");
	ok(e[0][2] > e[0][0] && e[GL_STYLE_RAMP - 1][0] >
	    e[GL_STYLE_RAMP - 1][2], "the error ramp runs blue to red");
	ok(fabsf(e[7][0] - e[7][1]) < 0.05f && fabsf(e[8][1] - e[8][2]) <
	    0.05f, "grey in the middle, at tau");
	ok(gl_style_level_rgb(9) == gl_style_level_rgb(1) &&
	    gl_style_level_rgb(0) != gl_style_level_rgb(1),
	    "eight level colours, then again");
}

int
main(void)
{
	test_names();
	test_defaults();
	test_height();
	test_ramps();
	return tap_done();
}
