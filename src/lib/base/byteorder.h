/* byteorder.h - little-endian integers and float32 runs in byte buffers: what
 * the fqm stream (stream.c) and the filled DEM file (dem_filled.c) are
 * written in, whatever the host. */
#ifndef TL_LE_H
#define TL_LE_H

#include <stddef.h>
#include <stdint.h>

static inline void
le_put32(unsigned char *p, uint32_t v)
{
	for (int i = 0; i < 4; i++)
		p[i] = (unsigned char)(v >> (8 * i));
}

static inline void
le_put64(unsigned char *p, uint64_t v)
{
	for (int i = 0; i < 8; i++)
		p[i] = (unsigned char)(v >> (8 * i));
}

static inline uint32_t
le_get32(const unsigned char *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
	    (uint32_t)p[3] << 24;
}

static inline uint64_t
le_get64(const unsigned char *p)
{
	return (uint64_t)le_get32(p) | (uint64_t)le_get32(p + 4) << 32;
}

/* n float32 (or uint32) values between host order and little-endian, in
 * place: nothing to do on a little-endian host. */
static inline void
le_swap32s(void *p, size_t n)
{
#if __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
	uint32_t *u = p;

	for (size_t i = 0; i < n; i++)
		u[i] = __builtin_bswap32(u[i]);
#else
	(void)p, (void)n;
#endif
}

#endif
