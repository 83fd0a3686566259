/* meristemd — what every handler shares: settings, sessions, workers, metrics. */
#ifndef MERISTEMD_APP_H
#define MERISTEMD_APP_H

#include "server/jobs.h"
#include "server/metrics.h"
#include "server/registry.h"
#include "server/session.h"
#include "server/settings.h"

typedef struct mer_app {
    const mer_settings *settings;
    mer_session_config session_config;
    mer_registry *registry;
    mer_jobs *jobs;
    mer_metrics *metrics;
} mer_app;

#endif
