/* dem_gdal_env.c - GDAL set up for the DEM reader, once per process
 * (drivers, a small block cache, no directory listing at each open), and
 * GDAL's messages caught for ours instead of printed. The leaf of the GDAL
 * adapter files (dem_gdal.c, dem_vrt.c, dem_mosaic.c), which all call it. */
#include <pthread.h>
#include <stdio.h>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>

#include "dem/dem_gdal.h"

#define CACHE_MB 4  /* GDAL's block cache unless GDAL_CACHEMAX says: each
                     * block is read once, so a window's worth is enough */

static pthread_once_t once = PTHREAD_ONCE_INIT;

static void
init(void)
{
	/* once per process: GDAL's configuration is global */
	GDALAllRegister();
	if (CPLGetConfigOption("GDAL_CACHEMAX", NULL) == NULL)
		GDALSetCacheMax64((GIntBig)CACHE_MB << 20);
	/* .aux.xml sidecars are read, never written (dem_gdal_open) */
	/* GDAL lists a file's directory at each open (for sidecars): with
	 * a mosaic of n tiles in one directory, n^2 entries read; it asks
	 * for each sidecar by name instead */
	if (CPLGetConfigOption("GDAL_DISABLE_READDIR_ON_OPEN", NULL) == NULL)
		CPLSetConfigOption("GDAL_DISABLE_READDIR_ON_OPEN", "TRUE");
}

void
dem_gdal_init(void)
{
	pthread_once(&once, init);
}

/* GDAL's messages, caught for ours (GDAL would print them). */
static void CPL_STDCALL
catch_error(CPLErr cls, CPLErrorNum no, const char *msg)
{
	dem_gdal_msg *c = CPLGetErrorHandlerUserData();

	(void)no;
	if (cls >= CE_Failure && c != NULL && c->msg[0] == '\0')
		snprintf(c->msg, sizeof c->msg, "%s", msg);
	else if (cls == CE_Warning && c != NULL && c->warning[0] == '\0')
		snprintf(c->warning, sizeof c->warning, "%s", msg);
}

void
dem_gdal_catch(dem_gdal_msg *m)
{
	m->msg[0] = m->warning[0] = '\0';
	CPLPushErrorHandlerEx(catch_error, m);
}

void
dem_gdal_release(void)
{
	CPLPopErrorHandler();
}
