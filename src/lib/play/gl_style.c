/* gl_style.c - styles and colour maps (see gl_style.h). */
#include "play/gl_style.h"

#include <assert.h>
#include <math.h>
#include <string.h>

static const char *colour_names[GL_NCOLOUR] = { "height", "level", "error" };

/* viridis (matplotlib, CC0) at t = k/15: perceptually uniform, readable
 * in grey and by colour-blind eyes; never near the crack test's magenta */
static const float viridis[GL_STYLE_RAMP][3] = {
	{ 0.267004f, 0.004874f, 0.329415f }, { 0.282656f, 0.100196f, 0.422160f },
	{ 0.277134f, 0.185228f, 0.489898f }, { 0.253935f, 0.265254f, 0.529983f },
	{ 0.221989f, 0.339161f, 0.548752f }, { 0.190631f, 0.407061f, 0.556089f },
	{ 0.163625f, 0.471133f, 0.558148f }, { 0.139147f, 0.533812f, 0.555298f },
	{ 0.120565f, 0.596422f, 0.543611f }, { 0.134692f, 0.658636f, 0.517649f },
	{ 0.208030f, 0.718701f, 0.472873f }, { 0.327796f, 0.773980f, 0.406640f },
	{ 0.477504f, 0.821444f, 0.318195f }, { 0.647257f, 0.858400f, 0.209861f },
	{ 0.824940f, 0.884720f, 0.106217f }, { 0.993248f, 0.906157f, 0.143936f },
};

/* Moreland's cool-warm ends and middle: below tau blue, above red */
static const float coolwarm[3][3] = {
	{ 0.230f, 0.299f, 0.754f }, { 0.865f, 0.865f, 0.865f },
	{ 0.706f, 0.016f, 0.150f },
};

/* Okabe-Ito, colour-blind safe; a level's colour is [level % 8] */
static const float levels[8][3] = {
	{ 0.902f, 0.624f, 0.000f }, { 0.337f, 0.706f, 0.914f },
	{ 0.000f, 0.620f, 0.451f }, { 0.941f, 0.894f, 0.259f },
	{ 0.000f, 0.447f, 0.698f }, { 0.835f, 0.369f, 0.000f },
	{ 0.800f, 0.475f, 0.655f }, { 0.600f, 0.600f, 0.600f },
};

void
gl_style_init(gl_style *s)
{
	s->colour = GL_BY_HEIGHT;
	s->light = 1, s->wire = 0, s->skirts = 1;
	s->background[0] = 0.62f, s->background[1] = 0.72f;
	s->background[2] = 0.82f;
}

const char *
gl_style_colour_name(enum gl_colour c)
{
	return c < GL_NCOLOUR ? colour_names[c] : "?";
}

int
gl_style_colour_parse(const char *name, enum gl_colour *c)
{
	for (int k = 0; k < GL_NCOLOUR; k++)
		if (strcmp(name, colour_names[k]) == 0) {
			*c = (enum gl_colour)k;
			return 0;
		}
	return -1;
}

void
gl_style_ramp(enum gl_colour c, float ramp[GL_STYLE_RAMP][3])
{
	if (c != GL_BY_ERROR) {
		memcpy(ramp, viridis, sizeof viridis);
		return;
	}
	for (int k = 0; k < GL_STYLE_RAMP; k++) {
		double x = 2.0 * k / (GL_STYLE_RAMP - 1);
		int i = x >= 1 ? 1 : 0;
		for (int a = 0; a < 3; a++)
			ramp[k][a] = (float)(coolwarm[i][a] + (x - i) *
			    (coolwarm[i + 1][a] - coolwarm[i][a]));
	}
}

const float *
gl_style_level_rgb(int level)
{
	assert(level >= 0);
	return levels[level % 8];
}

void
gl_style_height_rgb(double t, unsigned char rgb[3])
{
	double x;
	int i;

	t = t < 0 ? 0 : t > 1 ? 1 : t;
	x = t * (GL_STYLE_RAMP - 1);
	i = (int)x < GL_STYLE_RAMP - 2 ? (int)x : GL_STYLE_RAMP - 2;
	for (int a = 0; a < 3; a++) {
		double c = viridis[i][a] + (x - i) *
		    (viridis[i + 1][a] - viridis[i][a]);
		rgb[a] = (unsigned char)lrint(c * 255);
	}
}
