/* meristemd — the /v1 handlers. Each answers one route; `id` is the session id
 * from the path, or NULL. */
#ifndef MERISTEMD_API_H
#define MERISTEMD_API_H

#include <microhttpd.h>

#include "server/request.h"

/* Whether session `id` is known and not loaded yet: then its load (a
 * checkpoint and journal read, a replay) is handed to a worker, so that the
 * HTTP thread goes on serving its other connections, and the request is
 * suspended, to be routed again once the load is done (`*result` is what to
 * return to libmicrohttpd). Once per request. */
bool merd_api_load_first(merd_request *req, const char *id, enum MHD_Result *result);

enum MHD_Result merd_api_health(merd_request *req, const char *id);
enum MHD_Result merd_api_presets(merd_request *req, const char *id);
enum MHD_Result merd_api_metrics(merd_request *req, const char *id);
enum MHD_Result merd_api_list(merd_request *req, const char *id);
enum MHD_Result merd_api_create(merd_request *req, const char *id);
enum MHD_Result merd_api_get(merd_request *req, const char *id);
enum MHD_Result merd_api_delete(merd_request *req, const char *id);
enum MHD_Result merd_api_edits(merd_request *req, const char *id);
enum MHD_Result merd_api_snapshot(merd_request *req, const char *id);
enum MHD_Result merd_api_cancel(merd_request *req, const char *id);
enum MHD_Result merd_api_revisions(merd_request *req, const char *id);
enum MHD_Result merd_api_skeleton(merd_request *req, const char *id);
enum MHD_Result merd_api_functions(merd_request *req, const char *id);
enum MHD_Result merd_api_lsystem(merd_request *req, const char *id);

/* The query parameters (NULL-terminated) of snapshot options, which a
 * GLB-answered edit reads, and those of snapshot.glb: the options and revision. */
extern const char *const merd_api_glb_option_keys[];
extern const char *const merd_api_snapshot_keys[];

#endif
