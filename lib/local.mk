# libmeristem. Everything is built once into a convenience library that the unit
# tests link whole; the installed shared library exports only the mer_ prefix.
noinst_LTLIBRARIES += lib/libmeristem-core.la
lib_libmeristem_core_la_SOURCES = \
	lib/core/alloc.h \
	lib/core/alloc.c \
	lib/core/array.h \
	lib/core/atan2.h \
	lib/core/bytes.h \
	lib/core/hash.h \
	lib/core/perlin.h \
	lib/core/perlin.c \
	lib/core/parallel.h \
	lib/core/parallel.c \
	lib/core/vec.h \
	lib/result.c \
	lib/rng.c \
	lib/params.c \
	lib/params_io.h \
	lib/params_io.c \
	lib/skeleton/skeleton.h \
	lib/skeleton/skeleton.c \
	lib/skeleton/pipe.c \
	lib/env/env.h \
	lib/env/env.c \
	lib/env/markers.c \
	lib/env/markers_grid.h \
	lib/env/markers_near.h \
	lib/env/markers_near.c \
	lib/env/shadow.c \
	lib/env/shadow_batch.c \
	lib/env/solid.c \
	lib/env/obstacles.c \
	lib/env/volumes.c \
	lib/env/noise.h \
	lib/env/noise.c \
	lib/env/poisson.c \
	lib/env/voronoi.c \
	lib/models/model.h \
	lib/models/registry.c \
	lib/models/p09/p09.h \
	lib/models/p09/p09.c \
	lib/models/p09/environment.c \
	lib/models/p09/fate.c \
	lib/models/p09/borchert_honda.c \
	lib/models/p09/priority.c \
	lib/models/p09/schedule.c \
	lib/models/p09/shoot.c \
	lib/models/p09/shedding.c \
	lib/models/p09/params_p09.c \
	lib/models/runions/runions.h \
	lib/models/runions/runions.c \
	lib/models/runions/associate.c \
	lib/models/forest/forest.h \
	lib/models/forest/forest.c \
	lib/models/forest/forest_io.c \
	lib/models/forest/mirror.c \
	lib/models/forest/sow.c \
	lib/models/forest/sow_text.c \
	lib/models/guiding/guiding.h \
	lib/models/guiding/guiding.c \
	lib/models/guiding/graph.c \
	lib/models/guiding/guide.c \
	lib/models/guiding/dijkstra.c \
	lib/models/guiding/endpoints.c \
	lib/models/guiding/tree.c \
	lib/models/lsystem/lsystem.h \
	lib/models/lsystem/lsystem_private.h \
	lib/models/lsystem/expr.c \
	lib/models/lsystem/string.c \
	lib/models/lsystem/parse_private.h \
	lib/models/lsystem/parse.c \
	lib/models/lsystem/parse_production.c \
	lib/models/lsystem/derive.c \
	lib/models/lsystem/turtle.c \
	lib/models/lsystem/model_private.h \
	lib/models/lsystem/model.c \
	lib/models/lsystem/draw.c \
	lib/models/inverse/gfunc.h \
	lib/models/inverse/gfunc.c \
	lib/models/inverse/funcfile.c \
	lib/models/inverse/inverse.h \
	lib/models/inverse/def.c \
	lib/models/inverse/text.c \
	lib/models/inverse/silhouette.c \
	lib/models/inverse/order.c \
	lib/models/inverse/heading.c \
	lib/models/inverse/scale.c \
	lib/models/inverse/lifespan.c \
	lib/models/inverse/shoot.c \
	lib/models/inverse/phyllotaxis.c \
	lib/models/inverse/development.c \
	lib/models/inverse/radius.c \
	lib/models/inverse/build.c \
	lib/models/inverse/memory.c \
	lib/models/inverse/regrow.c \
	lib/models/inverse/inverse.c \
	lib/models/inverse/populus.c \
	lib/models/inverse/species.c \
	lib/scene.c \
	lib/scene_clone.c \
	lib/scene_io.c \
	lib/scene_env.c \
	lib/scene_read.c \
	lib/step_report.c \
	lib/edit.c \
	lib/brush.c \
	lib/symmetry.c \
	lib/symmetry.h \
	lib/presets.c \
	lib/presets_lsystem.h \
	lib/presets_lsystem.c \
	lib/presets_inverse.h \
	lib/presets_inverse.c \
	lib/mesh/mesh_private.h \
	lib/mesh/build.c \
	lib/mesh/axes.c \
	lib/mesh/tube.c \
	lib/mesh/leaves.c \
	lib/mesh/color.c \
	lib/mesh/joints.c \
	lib/mesh/joints_close.c \
	lib/mesh/joints_plan.c \
	lib/mesh/implicit/implicit.h \
	lib/mesh/implicit/segment.c \
	lib/mesh/implicit/row.c \
	lib/mesh/implicit/blend.c \
	lib/mesh/implicit/pcm.c \
	lib/mesh/implicit/bounded.c \
	lib/mesh/implicit/mtet.c \
	lib/mesh/implicit/junction.c \
	lib/mesh/implicit/gradient.c \
	lib/mesh/implicit/patch.c \
	lib/mesh/implicit/walk.h \
	lib/mesh/implicit/walk.c \
	lib/mesh/implicit/dc.c \
	lib/mesh/implicit/grade.c \
	lib/scene_private.h \
	lib/version.c \
	lib/gltf/gltf_private.h \
	lib/gltf/tinygltf_private.h \
	lib/gltf/tinygltf.cc \
	lib/gltf/writer.cc \
	lib/gltf/tree.cc \
	lib/gltf/meshopt.cc \
	lib/gltf/write.cc \
	lib/gltf/read.cc
lib_libmeristem_core_la_LIBADD = -lm

lib_LTLIBRARIES += lib/libmeristem.la
lib_libmeristem_la_SOURCES =
# An empty C++ source makes libtool link with the C++ driver (tinygltf needs libstdc++).
nodist_EXTRA_lib_libmeristem_la_SOURCES = lib/link-as-cxx.cc
lib_libmeristem_la_LIBADD = lib/libmeristem-core.la
lib_libmeristem_la_LDFLAGS = -version-info $(MERISTEM_LT_VERSION) -Wl,--version-script=$(srcdir)/lib/libmeristem.map
lib_libmeristem_la_DEPENDENCIES = lib/libmeristem-core.la $(srcdir)/lib/libmeristem.map
EXTRA_DIST += lib/libmeristem.map

include_HEADERS = lib/meristem.h
meristemincludedir = $(includedir)/meristem
meristeminclude_HEADERS = \
	lib/meristem/result.h \
	lib/meristem/alloc.h \
	lib/meristem/rng.h \
	lib/meristem/params.h \
	lib/meristem/fate.h \
	lib/meristem/markers.h \
	lib/meristem/shadow.h \
	lib/meristem/scene.h \
	lib/meristem/edit.h \
	lib/meristem/presets.h \
	lib/meristem/version.h \
	lib/meristem/gltf.h \
	lib/meristem/mesh.h \
	lib/meristem/sow.h
