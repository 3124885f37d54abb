/* plan_word.c - quoting a word of the plan for sh and make (a leaf). */
#include "jobs/plan_impl.h"

/* A word for the shell, single-quoted; for a Makefile also as make
 * reads a variable's value: $ doubled, and a '#' (a comment) escaped by a
 * backslash, the n backslashes before it doubled (make halves them, and
 * takes the rest literally). A newline no Makefile carries: plan_write
 * refuses it first (carriable). */
void
plan_word(FILE *f, const char *w, int make)
{
	int bs = 0;

	fputc('\'', f);
	for (const char *p = w; *p; p++) {
		if (*p == '\\' && make) {
			bs++;
			continue;
		}
		for (int k = 0; k < (*p == '#' && make ? 2 * bs + 1 : bs); k++)
			fputc('\\', f);
		bs = 0;
		if (*p == '\'')
			fputs("'\\''", f);
		else if (*p == '$' && make)
			fputs("$$", f);
		else
			fputc(*p, f);
	}
	while (bs-- > 0)
		fputc('\\', f);
	fputc('\'', f);
}

void
plan_words(FILE *f, const char *const *w, int n, int make)
{
	for (int i = 0; i < n; i++) {
		fputc(' ', f);
		plan_word(f, w[i], make);
	}
}
