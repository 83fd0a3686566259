/* meristemd — what every handler shares: settings, sessions, workers, metrics. */
#ifndef MERISTEMD_APP_H
#define MERISTEMD_APP_H

#include "server/jobs.h"
#include "server/metrics.h"
#include "server/registry.h"
#include "server/session.h"
#include "server/settings.h"

typedef struct merd_app {
    const merd_settings *settings;
    merd_session_config session_config;
    merd_registry *registry;
    merd_jobs *jobs;
    merd_metrics *metrics;
} merd_app;

#endif
