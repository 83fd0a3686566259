/* meristemd — the /v1 handlers. Each answers one route; `id` is the session id
 * from the path, or NULL. */
#ifndef MERISTEMD_API_H
#define MERISTEMD_API_H

#include <microhttpd.h>

#include "server/request.h"

enum MHD_Result mer_api_health(mer_request *req, const char *id);
enum MHD_Result mer_api_presets(mer_request *req, const char *id);
enum MHD_Result mer_api_metrics(mer_request *req, const char *id);
enum MHD_Result mer_api_list(mer_request *req, const char *id);
enum MHD_Result mer_api_create(mer_request *req, const char *id);
enum MHD_Result mer_api_get(mer_request *req, const char *id);
enum MHD_Result mer_api_delete(mer_request *req, const char *id);
enum MHD_Result mer_api_edits(mer_request *req, const char *id);
enum MHD_Result mer_api_snapshot(mer_request *req, const char *id);
enum MHD_Result mer_api_cancel(mer_request *req, const char *id);

#endif
