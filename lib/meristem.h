/* meristem — self-organizing tree models (Palubicki et al. 2009) as a library.
 *
 * The umbrella header: include this, link with `pkg-config --libs meristem`.
 * Every public name starts with `mer_`; the shared library exports nothing else.
 * libmeristem does no I/O: callers pass bytes in and get bytes back.
 */
#ifndef MERISTEM_H
#define MERISTEM_H

#include <meristem/result.h>
#include <meristem/alloc.h>
#include <meristem/version.h>
#include <meristem/rng.h>
#include <meristem/params.h>
#include <meristem/fate.h>
#include <meristem/markers.h>
#include <meristem/shadow.h>
#include <meristem/scene.h>
#include <meristem/edit.h>
#include <meristem/presets.h>
#include <meristem/gltf.h>
#include <meristem/sow.h>

#endif
