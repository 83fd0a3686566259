# Unit tests in C (C++ where tinygltf reads our output back), with cmocka.
UNIT_LDADD = lib/libmeristem-core.la $(CMOCKA_LIBS)
UNIT_CPPFLAGS = $(AM_CPPFLAGS) $(CMOCKA_CFLAGS)

check_PROGRAMS += tests/unit/test_result
tests_unit_test_result_SOURCES = tests/unit/test_result.c
tests_unit_test_result_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_result_LDADD = $(UNIT_LDADD)

check_PROGRAMS += tests/unit/test_gltf
tests_unit_test_gltf_SOURCES = tests/unit/test_gltf.cc
tests_unit_test_gltf_CPPFLAGS = $(UNIT_CPPFLAGS)
tests_unit_test_gltf_LDADD = $(UNIT_LDADD)

TESTS += $(check_PROGRAMS)
