# The HTTP contract: shipped in the tarball, read by the API tests.
EXTRA_DIST += $(srcdir)/proto
