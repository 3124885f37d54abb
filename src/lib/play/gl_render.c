/* gl_render.c - the terrain's shaders and blocks (see gl_render.h). */
#include "play/gl_render.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "play/gl_ctx.h"

#define STR_(x) #x
#define STR(x) STR_(x)

enum { MODE_RAMP_HEIGHT, MODE_FLAT, MODE_RAMP_ERROR };

static const char *terrain_vs =
    "#version 330 core\n"
    "layout(location = 0) in vec3 pos;\n"
    "layout(location = 1) in vec3 nrm;\n"
    "layout(location = 2) in vec2 val; /* height, E */\n"
    "uniform mat4 proj, rot;\n"
    "uniform vec3 offset; /* block origin - eye */\n"
    "uniform int mode;\n"
    "uniform float zlo, zinv, tau;\n"
    "uniform vec2 corner; /* the block's (0, 0) in level units */\n"
    "uniform float scale; /* level-0 cells a level cell */\n"
    "out vec3 n;\n"
    "out vec2 grid; /* level-0 column, row */\n"
    "out float t, skirt;\n"
    "void main() {\n"
    "	int k = gl_VertexID, s = (k - " STR(PYRAMID_N) ") / " STR(BT_SIZE) ";\n"
    "	int u = (k - " STR(PYRAMID_N) ") % " STR(BT_SIZE) ";\n"
    "	ivec2 g = k < " STR(PYRAMID_N) " ? ivec2(k % " STR(BT_SIZE) ", k / "
    STR(BT_SIZE) ") :\n"
    "	    s == 0 ? ivec2(u, 0) : s == 1 ? ivec2(u, " STR(BT_CELLS) ") :\n"
    "	    s == 2 ? ivec2(0, u) : ivec2(" STR(BT_CELLS) ", u);\n"
    "	grid = (vec2(g) + corner) * scale;\n"
    "	gl_Position = proj * rot * vec4(pos + offset, 1.0);\n"
    "	n = nrm;\n"
    "	if (mode == 2)\n"
    "		t = clamp(0.5 + log2(max(val.y, 1e-30) / tau) / 8.0, 0.0, 1.0);\n"
    "	else\n"
    "		t = clamp((val.x - zlo) * zinv, 0.0, 1.0);\n"
    "	skirt = k >= " STR(PYRAMID_N) " ? 1.0 : 0.0;\n"
    "}\n";

static const char *terrain_fs =
    "#version 330 core\n"
    "in vec3 n;\n"
    "in vec2 grid;\n"
    "in float t, skirt;\n"
    "uniform int mode, lines;\n"
    "uniform vec2 edge; /* the DEM's last column and row */\n"
    "uniform vec3 ramp[" STR(GL_STYLE_RAMP) "], solid, light;\n"
    "uniform float ambient;\n"
    "out vec4 colour;\n"
    "void main() {\n"
    "	vec3 c;\n"
    "	/* blocks are padded past the DEM: cut them at its edge */\n"
    "	if (any(greaterThan(grid, edge + 1e-3)))\n"
    "		discard;\n"
    "	/* no skirts on the DEM's own edges: nothing to close there */\n"
    "	if (skirt > 0.0 && (any(lessThan(grid, vec2(1e-3))) ||\n"
    "	    any(greaterThan(grid, edge - 1e-3))))\n"
    "		discard;\n"
    "	if (lines == 1 && skirt > 0.0)\n"
    "		discard;\n"
    "	if (mode == 1) {\n"
    "		c = solid;\n"
    "	} else {\n"
    "		float x = t * float(" STR(GL_STYLE_RAMP) " - 1);\n"
    "		int i = min(int(x), " STR(GL_STYLE_RAMP) " - 2);\n"
    "		c = mix(ramp[i], ramp[i + 1], x - float(i));\n"
    "	}\n"
    "	float d = max(dot(normalize(n), light), 0.0);\n"
    "	colour = vec4(c * (ambient + (1.0 - ambient) * d), 1.0);\n"
    "}\n";

#define AMBIENT 0.3f

enum { U_PROJ, U_ROT, U_OFFSET, U_MODE, U_ZLO, U_ZINV, U_TAU, U_LINES,
	U_RAMP, U_SOLID, U_LIGHT, U_AMBIENT, U_CORNER, U_SCALE, U_EDGE, NU };
static const char *unames[NU] = { "proj", "rot", "offset", "mode", "zlo",
	"zinv", "tau", "lines", "ramp", "solid", "light", "ambient", "corner",
	"scale", "edge" };

struct gl_render {
	const world *w;
	GLuint prog;
	GLint u[NU];
	float zlo, zinv;         /* the height map */
	/* this frame: */
	gl_style s;
	double eye[3];
	gl_render_stats *st;
};

/* A block's state, the cache's user pointer: its buffers and the
 * triangles they hold. */
typedef struct {
	GLuint vao, vbo, ibo;
	GLsizei count;
	int skirts;              /* the index buffer has skirts */
	mesh_tris tris;          /* triangles at tau */
	double tau;              /* the tau tris was built for; NAN: none */
} gpu;

static void
height_range(gl_render *r)
{
	const pyramid_level *L = &r->w->ix.lev[0];
	double lo = INFINITY, hi = -INFINITY;

	/* level 0 is the DEM: its range, whatever coarser levels solved */
	for (int k = 0; k < L->blocks[0] * L->blocks[1]; k++)
		lo = fmin(lo, L->zmin[k]), hi = fmax(hi, L->zmax[k]);
	if (!(lo < hi))
		hi = lo + 1;
	r->zlo = (float)lo;
	r->zinv = (float)(1 / (hi - lo));
}

gl_render *
gl_render_new(const world *w, tl_err *e)
{
	gl_render *r = tl_alloc(1, sizeof *r, e);

	if (r == NULL)
		return NULL;
	r->w = w;
	if ((r->prog = gl_ctx_program(terrain_vs, terrain_fs, e)) == 0) {
		gl_render_free(r);
		return NULL;
	}
	for (int k = 0; k < NU; k++)
		r->u[k] = glGetUniformLocation(r->prog, unames[k]);
	height_range(r);
	gl_style_init(&r->s);
	return r;
}

void
gl_render_free(gl_render *r)
{
	if (r == NULL)
		return;
	if (r->prog != 0)
		glDeleteProgram(r->prog);
	free(r);
}

void
gl_render_release(void *user, void *ctx)
{
	gpu *g = user;

	(void)ctx;
	glDeleteVertexArrays(1, &g->vao);
	glDeleteBuffers(1, &g->vbo);
	glDeleteBuffers(1, &g->ibo);
	mesh_tris_free(&g->tris);
	free(g);
}

static void
set_ramp(gl_render *r, enum gl_colour c)
{
	float ramp[GL_STYLE_RAMP][3];

	gl_style_ramp(c, ramp);
	glUniform3fv(r->u[U_RAMP], GL_STYLE_RAMP, &ramp[0][0]);
}

/* The colouring and light of the style (after the wireframe's lines). */
static void
set_mode(gl_render *r)
{
	glUniform1i(r->u[U_MODE], r->s.colour == GL_BY_LEVEL ? MODE_FLAT :
	    r->s.colour == GL_BY_ERROR ? MODE_RAMP_ERROR : MODE_RAMP_HEIGHT);
	glUniform1f(r->u[U_AMBIENT], r->s.light ? AMBIENT : 1.0f);
}

/* Depth, no culling (bintree triangles alternate in orientation), and
 * the wireframe's offset of the surface behind its lines. */
static void
set_state(const gl_style *s)
{
	glEnable(GL_DEPTH_TEST);
	glDisable(GL_BLEND);
	glDisable(GL_CULL_FACE);
	glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
	if (s->wire) {
		glEnable(GL_POLYGON_OFFSET_FILL);
		glPolygonOffset(1, 1);
	} else
		glDisable(GL_POLYGON_OFFSET_FILL);
}

void
gl_render_begin(gl_render *r, const camera *c, const gl_style *s,
    gl_render_stats *st)
{
	/* the view turns about the eye; blocks are placed relative to it */
	camera rc = *c;
	float view[16], proj[16];
	/* towards the light: from the north-west, 45 degrees up, as in
	 * cartographic hill shading */
	float light[3] = { -0.5f, 0.5f, 0.70710678f };

	for (int k = 0; k < 3; k++) {
		r->eye[k] = c->eye[k];
		rc.target[k] = c->target[k] - c->eye[k];
		rc.eye[k] = 0;
	}
	camera_matrices(&rc, view, proj);
	r->s = *s;
	r->st = st;
	memset(st, 0, sizeof *st);
	glViewport(0, 0, c->width, c->height);
	glClearColor(s->background[0], s->background[1], s->background[2], 1);
	glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
	set_state(s);
	glUseProgram(r->prog);
	glUniformMatrix4fv(r->u[U_PROJ], 1, GL_FALSE, proj);
	glUniformMatrix4fv(r->u[U_ROT], 1, GL_FALSE, view);
	glUniform3fv(r->u[U_LIGHT], 1, light);
	glUniform1f(r->u[U_ZLO], r->zlo);
	glUniform1f(r->u[U_ZINV], r->zinv);
	glUniform1i(r->u[U_LINES], 0);
	glUniform2f(r->u[U_EDGE], r->w->ix.size0[0] - 1.0f,
	    r->w->ix.size0[1] - 1.0f);
	set_mode(r);
	set_ramp(r, s->colour);
}

/* The block's buffers, its vertices uploaded; the cache's copy of them
 * then goes (on llvmpipe the buffer is in RAM too: counted once in the
 * cap, kept once). */
static gpu *
gpu_new(cblock *cb, tl_err *e)
{
	const mesh_verts *v = cache_block_verts(cb);
	gpu *g = tl_alloc(1, sizeof *g, e);
	GLsizeiptr n3 = MESH_NV * 3 * sizeof(float);
	GLsizeiptr n2 = MESH_NV * 2 * sizeof(float);

	if (g == NULL)
		return NULL;
	assert(v->pos != NULL);
	g->skirts = -1;
	g->tau = NAN;
	glGenVertexArrays(1, &g->vao);
	glBindVertexArray(g->vao);
	glGenBuffers(1, &g->vbo);
	glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
	glBufferData(GL_ARRAY_BUFFER, 2 * n3 + n2, NULL, GL_STATIC_DRAW);
	glBufferSubData(GL_ARRAY_BUFFER, 0, n3, v->pos);
	glBufferSubData(GL_ARRAY_BUFFER, n3, n3, v->nrm);
	glBufferSubData(GL_ARRAY_BUFFER, 2 * n3, n2, v->val);
	glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, (void *)0);
	glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, (void *)n3);
	glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 0, (void *)(2 * n3));
	for (GLuint a = 0; a < 3; a++)
		glEnableVertexAttribArray(a);
	glGenBuffers(1, &g->ibo);
	glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ibo);
	cache_block_set_user(cb, g);
	cache_block_verts_done(cb);
	return g;
}

/* Rounded down to a quarter power of two: the tolerance is kept, and a
 * camera moving smoothly rebuilds a block's triangles only now and then. */
static double
tau_step(double tau)
{
	return tau > 0 ? exp2(floor(4 * log2(tau)) / 4) : -1;
}

/* New triangles at tau q, counted in the cache, into the index buffer:
 * 1, 0 when the cache has no room for them, -1 on error. */
static int
rebuild(gl_render *r, cache *k, cblock *cb, gpu *g, double q, tl_err *e)
{
	uint32_t *p;

	if (mesh_tris_build(cache_block_data(cb), q, r->s.skirts, &g->tris,
	    e) < 0)
		return -1;
	/* the builder doubles its array: give back what it did not use */
	if (g->tris.n < g->tris.cap &&
	    (p = realloc(g->tris.idx, g->tris.n * sizeof *p)) != NULL)
		g->tris.idx = p, g->tris.cap = g->tris.n;
	g->tau = q;
	if (!cache_account(k, cb, g->tris.cap * sizeof *g->tris.idx)) {
		mesh_tris_free(&g->tris);
		g->tau = NAN;
		return 0;
	}
	glBindVertexArray(g->vao);
	glBufferData(GL_ELEMENT_ARRAY_BUFFER,
	    (GLsizeiptr)(g->tris.n * sizeof *g->tris.idx), g->tris.idx,
	    GL_STATIC_DRAW);
	g->count = (GLsizei)g->tris.n;
	g->skirts = r->s.skirts;
	return 1;
}

/* The triangles' edges over the surface, then the style back. */
static void
draw_wire(gl_render *r, const gpu *g)
{
	static const float ink[3] = { 0.08f, 0.08f, 0.08f };

	glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
	glUniform1i(r->u[U_LINES], 1);
	glUniform1i(r->u[U_MODE], MODE_FLAT);
	glUniform3fv(r->u[U_SOLID], 1, ink);
	glUniform1f(r->u[U_AMBIENT], 1);
	glDrawElements(GL_TRIANGLES, g->count, GL_UNSIGNED_INT, 0);
	glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
	glUniform1i(r->u[U_LINES], 0);
	set_mode(r);
}

static void
count(gl_render_stats *st, const gpu *g, int level)
{
	st->blocks++;
	st->tris += g->tris.tris;
	st->skirts += g->tris.skirts;
	if (level < 32)
		st->per_level[level]++;
	if (level + 1 > st->levels)
		st->levels = level + 1;
}

int
gl_render_draw(gl_render *r, cache *k, cblock *cb, double tau, tl_err *e)
{
	const pyramid_block *b = cache_block_data(cb);
	double q = tau_step(tau);
	gpu *g = cache_block_user(cb);
	float off[3];
	int rc;

	if (g == NULL && (g = gpu_new(cb, e)) == NULL)
		return -1;
	if (!(g->tau == q) || g->tris.idx == NULL || g->skirts != r->s.skirts)
		if ((rc = rebuild(r, k, cb, g, q, e)) <= 0)
			return rc;
	for (int a = 0; a < 3; a++)
		off[a] = (float)(cache_block_verts(cb)->origin[a] - r->eye[a]);
	glUniform3fv(r->u[U_OFFSET], 1, off);
	glUniform2f(r->u[U_CORNER], (float)(b->bi * BT_CELLS),
	    (float)(b->bj * BT_CELLS));
	glUniform1f(r->u[U_SCALE], (float)(1L << b->level));
	glUniform1f(r->u[U_TAU], (float)(q > 0 ? q : 0.01));
	glUniform3fv(r->u[U_SOLID], 1, gl_style_level_rgb(b->level));
	glBindVertexArray(g->vao);
	glDrawElements(GL_TRIANGLES, g->count, GL_UNSIGNED_INT, 0);
	if (r->s.wire)
		draw_wire(r, g);
	count(r->st, g, b->level);
	return 1;
}

void
gl_render_height_rgb(const gl_render *r, double z, unsigned char rgb[3])
{
	gl_style_height_rgb((z - r->zlo) * r->zinv, rgb);
}
