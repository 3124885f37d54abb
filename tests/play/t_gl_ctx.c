/* t_gl_ctx - the headless context (EGL, llvmpipe without a GPU): its
 * size, a clear read back top-down, shader programs and their errors. */
#include "fixture.h"

static const char *vs =
    "#version 330 core\n"
    "void main() { gl_Position = vec4(0.0, 0.0, 0.0, 1.0); }\n";
static const char *fs =
    "#version 330 core\n"
    "out vec4 c;\n"
    "void main() { c = vec4(1.0); }\n";

static void
test_read(gl_ctx *g)
{
	unsigned char rgb[64 * 48 * 3];
	int w, h, red = 1;

	gl_ctx_size(g, &w, &h);
	ok(w == 64 && h == 48 && gl_ctx_glfw(g) == NULL,
	    "a 64x48 framebuffer, no window");
	glViewport(0, 0, w, h);
	glClearColor(1, 0, 0, 1);
	glClear(GL_COLOR_BUFFER_BIT);
	/* the top 8 rows green: GL counts rows from the bottom */
	glEnable(GL_SCISSOR_TEST);
	glScissor(0, h - 8, w, 8);
	glClearColor(0, 1, 0, 1);
	glClear(GL_COLOR_BUFFER_BIT);
	glDisable(GL_SCISSOR_TEST);
	gl_ctx_read_rgb(g, rgb);
	for (int k = 8 * w; k < w * h; k++)
		red &= rgb[3 * k] == 255 && rgb[3 * k + 1] == 0;
	ok(rgb[0] == 0 && rgb[1] == 255 && rgb[3 * (8 * w - 1) + 1] == 255 &&
	    red, "read back top-down: the top rows first");
	gl_ctx_present(g);
}

static void
test_programs(void)
{
	tl_err e;
	GLuint p = gl_ctx_program(vs, fs, &e);

	ok(p != 0, "a program compiles and links");
	glDeleteProgram(p);
	ok(gl_ctx_program(vs, "#version 330 core\nvoid main() { x; }\n",
	    &e) == 0 && strstr(e.msg, "OpenGL: shader: ") != NULL,
	    "a broken shader: 0, the compiler's log (%.40s...)", e.msg);
}

int
main(int argc, char **argv)
{
	gl_ctx *g;

	(void)argc;
	if (fx_init(argv[0], "t_gl_ctx") < 0)
		return 1;
	if ((g = fx_headless(64, 48)) != NULL) {
		test_read(g);
		test_programs();
		gl_ctx_close(g);
		ok(1, "closed");
	}
	fx_done();
	return tap_done();
}
