/* meristem — parameters in a checkpoint by name (params_io.c), so that a
 * checkpoint outlives new parameters. Not installed. */
#ifndef MERISTEM_PARAMS_IO_H
#define MERISTEM_PARAMS_IO_H

#include <meristem/params.h>
#include <meristem/result.h>

#include "core/bytes.h"

/* Writes every named field of `p` (not NULL; all-zero: the defaults) and its
 * keyframe schedules as a section of named entries. `p->model` is not
 * written: the checkpoint names its model beside the model's state. Running
 * out of memory marks `out` (its oom). O(fields). */
void merp_params_save(const mer_params *p, merp_bytes_out *out);

/* Reads a section merp_params_save wrote into `*p`, starting from the
 * defaults: a field the section lacks keeps its default (an older writer). A
 * name this build does not know (a newer writer), a name given twice, a value
 * out of its range or a damaged entry is MER_ERR_FORMAT naming the field or
 * "params". Neither the model nor the cross-field rules are checked: the
 * caller validates. O(fields²). */
mer_result merp_params_load(merp_bytes_in *in, mer_params *p, mer_error *err);

#endif
