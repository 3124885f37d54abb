/* gl_style.h - how the terrain is drawn: the colour mode, light,
 * wireframe, skirts and background, and the colour maps. No GL here. */
#ifndef TL_GL_STYLE_H
#define TL_GL_STYLE_H

enum gl_colour { GL_BY_HEIGHT, GL_BY_LEVEL, GL_BY_ERROR, GL_NCOLOUR };

typedef struct {
	enum gl_colour colour;
	int light;           /* directional light + ambient; 0: flat colours */
	int wire;            /* triangle edges over the surface */
	int skirts;          /* draw the skirts (mesh.h) */
	float background[3]; /* clear colour, 0..1 */
} gl_style;

void gl_style_init(gl_style *s);
const char *gl_style_colour_name(enum gl_colour c);
/* "height", "level" or "error"; -1 for another name. */
int gl_style_colour_parse(const char *name, enum gl_colour *c);

#define GL_STYLE_RAMP 16 /* colours of a ramp, interpolated between */

/* The ramp of a colour mode: viridis for heights, cool-warm (blue below
 * tau, grey at it, red above) for errors. */
void gl_style_ramp(enum gl_colour c, float ramp[GL_STYLE_RAMP][3]);
/* A level's colour (Okabe-Ito, level % 8). */
const float *gl_style_level_rgb(int level);
/* Viridis at t (clamped to 0..1), as 0..255. */
void gl_style_height_rgb(double t, unsigned char rgb[3]);

#endif
