# `make gallery`: every preset grown to its figure's size and rendered to
# gallery/PRESET.png through the brush client in headless Chromium (README.md, section Gallery).
gallery: all
	$(MKDIR_P) gallery
	MERISTEMD='$(abs_top_builddir)/server/meristemd' MER_WEB_ROOT='$(abs_top_builddir)/webroot' \
	CHROMIUM='$(CHROMIUM)' NODE_PATH='$(NODE_MODULES_DIR)' \
	  '$(NODE)' '$(abs_top_srcdir)/tests/gallery/gallery.js' gallery $(GALLERY_STEPS)
GALLERY_STEPS =
# `make gallery-junctions`: the README's figures of implicit junctions (a whole tree,
# its fork close-up, one fork at years 1, 4, 7, 10) to gallery/junctions-*.png.
gallery-junctions: all
	$(MKDIR_P) gallery
	MERISTEMD='$(abs_top_builddir)/server/meristemd' MER_WEB_ROOT='$(abs_top_builddir)/webroot' \
	CHROMIUM='$(CHROMIUM)' NODE_PATH='$(NODE_MODULES_DIR)' \
	  '$(NODE)' '$(abs_top_srcdir)/tests/gallery/junctions.js' gallery
clean-local: clean-gallery
clean-gallery:
	-rm -rf gallery
.PHONY: gallery gallery-junctions clean-gallery
EXTRA_DIST += tests/gallery/gallery.js tests/gallery/junctions.js
