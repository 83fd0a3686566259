# The brush client. meristemd serves `webroot/` from the build folder: web/'s own
# files plus the parts of three.js the page imports, copied from web/node_modules
# (installed by the quick start from web/package-lock.json). The copy keeps the
# node_modules/three/... paths, so web/ itself also works as a web root while
# editing the page. `make install` installs the same tree as $(pkgdatadir)/web.
webdir = $(pkgdatadir)/web
# The page's own files, from the top source folder; assemble.sh copies each one to
# the same path under webroot/ without the leading web/.
WEB_FILES = web/index.html web/style.css web/favicon.svg \
	web/js/app.js web/js/api.js web/js/util.js web/js/status.js \
	web/js/session.js web/js/constraint.js web/js/topbar.js web/js/input.js \
	web/js/models.js \
	web/js/tools/index.js web/js/tools/view.js web/js/tools/brush.js \
	web/js/tools/symmetry.js web/js/tools/hover.js web/js/tools/prune.js \
	web/js/tools/bend.js \
	web/js/panels/index.js web/js/panels/growth.js web/js/panels/view.js \
	web/js/panels/schedule.js web/js/panels/params.js web/js/panels/history.js \
	web/js/panels/time.js web/js/panels/lsystem.js web/js/panels/inverse.js \
	web/js/panels/gfunc.js \
	web/js/viewer/viewer.js web/js/viewer/loader.js web/js/viewer/picking.js \
	web/js/viewer/highlight.js web/js/viewer/lod.js web/js/viewer/probe.js \
	web/js/viewer/fork.js
THREE_PARTS = \
	LICENSE \
	build/three.module.js \
	build/three.core.js \
	examples/jsm/controls/OrbitControls.js \
	examples/jsm/loaders/GLTFLoader.js \
	examples/jsm/libs/meshopt_decoder.module.js \
	examples/jsm/utils/BufferGeometryUtils.js \
	examples/jsm/utils/SkeletonUtils.js
EXTRA_DIST += $(WEB_FILES) web/package.json web/package-lock.json web/assemble.sh

# make finds the prerequisites in $(srcdir) through VPATH.
webroot/.stamp: $(WEB_FILES) web/package-lock.json web/assemble.sh
	$(AM_V_GEN)$(SHELL) $(srcdir)/web/assemble.sh '$(srcdir)' '$(WEB_MODULES_DIR)' webroot \
		$(WEB_FILES) -- $(THREE_PARTS)

all-local: webroot/.stamp
install-data-local: webroot/.stamp
	$(MKDIR_P) '$(DESTDIR)$(webdir)'
	cd webroot && find . -type f ! -name .stamp | while read -r f; do \
	  $(MKDIR_P) "$(DESTDIR)$(webdir)/$${f%/*}" && \
	  $(INSTALL_DATA) "$$f" "$(DESTDIR)$(webdir)/$$f" || exit 1; done
uninstall-local:
	-rm -rf '$(DESTDIR)$(webdir)'
clean-local: clean-webroot
clean-webroot:
	-rm -rf webroot
.PHONY: clean-webroot
