// oiio_plugin.cpp - tl_oiio.so: OpenImageIO behind the C table of
// oiio_plugin.h. Every entry catches everything; errors become strings.
#include "raster/oiio_plugin.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

struct tl_oiio_img {
	std::unique_ptr<OIIO::ImageInput> in;
	OIIO::ImageSpec spec;
	OIIO::TypeDesc type; // what we ask OpenImageIO for
};

static void
seterr(char *err, size_t len, const std::string &s)
{
	if (err == nullptr || len == 0)
		return;
	std::string m = s.empty() ? "unknown OpenImageIO error" : s;
	while (!m.empty() && (m.back() == '\n' || m.back() == ' '))
		m.pop_back();
	// Multi-line messages: keep the first line, it names the problem.
	size_t nl = m.find('\n');
	if (nl != std::string::npos)
		m.resize(nl);
	snprintf(err, len, "%s", m.c_str());
}

// Native type in, native type out: OpenImageIO normalises integer
// conversions (int16 -> float gives v/32767), so never let it convert.
static bool
native(OIIO::TypeDesc t, tl_px *px, OIIO::TypeDesc *ask)
{
	switch (t.basetype) {
	case OIIO::TypeDesc::UINT8: *px = TL_PX_U8; break;
	case OIIO::TypeDesc::INT8: *px = TL_PX_I8; break;
	case OIIO::TypeDesc::UINT16: *px = TL_PX_U16; break;
	case OIIO::TypeDesc::INT16: *px = TL_PX_I16; break;
	case OIIO::TypeDesc::UINT32: *px = TL_PX_U32; break;
	case OIIO::TypeDesc::INT32: *px = TL_PX_I32; break;
	case OIIO::TypeDesc::HALF: // widening, not normalised
	case OIIO::TypeDesc::FLOAT:
		*px = TL_PX_F32;
		*ask = OIIO::TypeDesc::FLOAT;
		return true;
	case OIIO::TypeDesc::DOUBLE: *px = TL_PX_F64; break;
	default:
		return false;
	}
	*ask = OIIO::TypeDesc((OIIO::TypeDesc::BASETYPE)t.basetype);
	return true;
}

static tl_oiio_img *
img_open(const char *path, tl_oiio_info *info, char *err, size_t errlen)
{
	try {
		OIIO::attribute("threads", 1);
		OIIO::ImageSpec config;
		// PNG alpha would otherwise be premultiplied into Terrain-RGB.
		config.attribute("oiio:UnassociatedAlpha", 1);
		auto in = OIIO::ImageInput::open(path, &config);
		if (!in) {
			seterr(err, errlen, OIIO::geterror());
			return nullptr;
		}
		std::unique_ptr<tl_oiio_img> img(new tl_oiio_img);
		img->spec = in->spec();
		const OIIO::ImageSpec &s = img->spec;
		tl_px px;
		if (!native(s.channelformat(0), &px, &img->type)) {
			seterr(err, errlen, std::string("unsupported pixel type ") +
			    s.channelformat(0).c_str());
			return nullptr;
		}
		if (s.depth > 1) {
			seterr(err, errlen, "volume images are not supported");
			return nullptr;
		}
		if (s.width < 1 || s.height < 1 || s.nchannels < 1) {
			seterr(err, errlen, "empty image");
			return nullptr;
		}
		memset(info, 0, sizeof *info);
		info->width = s.width;
		info->height = s.height;
		info->nchannels = s.nchannels;
		info->type = px;
		info->bits = s.get_int_attribute("oiio:BitsPerSample",
		    (int)s.channelformat(0).size() * 8);
		// Tiled images must be read by whole tile rows: read_scanlines
		// on a tiled TIFF kills OpenImageIO 2.4.7 with SIGFPE.
		info->chunk = s.tile_width > 0 && s.tile_height > 0 ?
		    s.tile_height : 16;
		snprintf(info->format, sizeof info->format, "%s", in->format_name());
		img->in = std::move(in);
		return img.release();
	} catch (const std::exception &x) {
		seterr(err, errlen, x.what());
	} catch (...) {
		seterr(err, errlen, "unknown C++ exception in OpenImageIO");
	}
	return nullptr;
}

static int
img_read_rows(tl_oiio_img *img, int y0, int y1, int nch, void *buf,
    char *err, size_t errlen)
{
	try {
		const OIIO::ImageSpec &s = img->spec;
		bool ok;

		if (y0 < 0 || y1 > s.height || y0 >= y1 || nch < 1 ||
		    nch > s.nchannels) {
			seterr(err, errlen, "bad row or channel range");
			return -1;
		}
		if (s.tile_width > 0 && s.tile_height > 0)
			ok = img->in->read_tiles(0, 0, s.x, s.x + s.width,
			    s.y + y0, s.y + y1, s.z, s.z + (s.depth > 0 ? s.depth : 1),
			    0, nch, img->type, buf);
		else
			ok = img->in->read_scanlines(0, 0, s.y + y0, s.y + y1, s.z,
			    0, nch, img->type, buf);
		if (!ok) {
			seterr(err, errlen, img->in->geterror());
			return -1;
		}
		return 0;
	} catch (const std::exception &x) {
		seterr(err, errlen, x.what());
	} catch (...) {
		seterr(err, errlen, "unknown C++ exception in OpenImageIO");
	}
	return -1;
}

static void
img_close(tl_oiio_img *img)
{
	try {
		if (img != nullptr && img->in)
			img->in->close();
	} catch (...) {
	}
	delete img;
}

// The encoded file written out, every write checked: 0, or -1 + err.
static int
write_all(const char *path, const std::vector<unsigned char> &buf,
    char *err, size_t errlen)
{
	int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
	size_t off = 0;

	while (fd >= 0 && off < buf.size()) {
		ssize_t n = write(fd, buf.data() + off, buf.size() - off);
		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0) {
			int saved = errno;
			close(fd);
			errno = saved;
			fd = -1;
			break;
		}
		off += (size_t)n;
	}
	if (fd < 0 || close(fd) != 0) {
		seterr(err, errlen, std::string("write: ") + strerror(errno));
		return -1;
	}
	return 0;
}

static int
img_write_u8(const char *path, const char *format, int w, int h, int nch,
    const unsigned char *px, char *err, size_t errlen)
{
	try {
		OIIO::attribute("threads", 1);
		auto out = OIIO::ImageOutput::create(format);
		if (!out) {
			seterr(err, errlen, OIIO::geterror());
			return -1;
		}
		// Encoded in memory where the format allows, then written
		// here: OpenImageIO's writers (PNG) ignore a failed write (a
		// full disk, ulimit -f) and report success on a cut file.
		std::vector<unsigned char> buf;
		OIIO::Filesystem::IOVecOutput vec(buf);
		bool mem = out->supports("ioproxy") != 0;
		OIIO::ImageSpec spec(w, h, nch, OIIO::TypeDesc::UINT8);
		if (mem && !out->set_ioproxy(&vec))
			mem = false;
		if (!out->open(path, spec) ||
		    !out->write_image(OIIO::TypeDesc::UINT8, px) ||
		    !out->close()) {
			seterr(err, errlen, out->geterror());
			return -1;
		}
		return mem ? write_all(path, buf, err, errlen) : 0;
	} catch (const std::exception &x) {
		seterr(err, errlen, x.what());
	} catch (...) {
		seterr(err, errlen, "unknown C++ exception in OpenImageIO");
	}
	return -1;
}

static const tl_oiio_api api = {
	TL_OIIO_ABI, img_open, img_read_rows, img_close, img_write_u8
};

extern "C" __attribute__((visibility("default"))) const tl_oiio_api *
tl_oiio_plugin(void)
{
	return &api;
}
