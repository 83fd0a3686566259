# `make gallery`: every preset grown to its figure's size and rendered to
# gallery/PRESET.png through the brush client in headless Chromium (README.md, section Gallery).
gallery: all
	$(MKDIR_P) gallery
	MERISTEMD='$(abs_top_builddir)/server/meristemd' MER_WEB_ROOT='$(abs_top_builddir)/webroot' \
	CHROMIUM='$(CHROMIUM)' NODE_PATH='$(NODE_MODULES_DIR)' \
	  '$(NODE)' '$(abs_top_srcdir)/tests/gallery/gallery.js' gallery $(GALLERY_STEPS)
GALLERY_STEPS =
clean-local: clean-gallery
clean-gallery:
	-rm -rf gallery
.PHONY: gallery clean-gallery
EXTRA_DIST += tests/gallery/gallery.js
