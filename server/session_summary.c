/* meristemd — a session's summary, cached as JSON and as text when a batch is
 * accepted, so readers never wait for a running step (see session.h). */
#include "config.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "server/codec.h"
#include "server/session_private.h"

/* The summary of the scene as it is (caller holds `work`). */
static json_t *build_summary(merd_session *s, uint64_t revision)
{
    json_t *j = merd_json_summary(s->scene);
    const json_t *preset = json_object_get(s->spec, "preset");
    const json_t *seed = json_object_get(s->spec, "seed");
    json_object_set_new(j, "id", json_string(s->id));
    json_object_set_new(j, "revision", json_integer((json_int_t)revision));
    json_object_set_new(j, "preset", json_string(preset ? json_string_value(preset) : "default"));
    json_object_set_new(j, "seed", json_integer(seed ? json_integer_value(seed) : 0));
    const mer_params *p = mer_scene_params(s->scene);
    uint32_t node, slot;
    json_object_set_new(j, "constraint", mer_scene_constraint(s->scene, &node, &slot)
                                             ? json_pack("{s:i, s:i}", "node", (json_int_t)node,
                                                         "bud", (json_int_t)slot)
                                             : json_null());
    if (s->expires_at > 0) {
        // ttl_seconds at creation: when the session goes, as RFC 3339 UTC.
        char when[32];
        time_t t = (time_t)s->expires_at;
        struct tm tm;
        strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", gmtime_r(&t, &tm));
        json_object_set_new(j, "expires_at", json_string(when));
    }
    json_object_set_new(j, "params", merd_json_params(p));
    json_object_set_new(j, "schedule", merd_json_schedule(&p->schedule));
    return j;
}

/* Serializes `j` without its closing brace, so "running" can be appended. */
static char *open_text(const json_t *j)
{
    char *text = json_dumps(j, MERD_JSON_DUMP_FLAGS);
    if (text != NULL)
        text[strlen(text) - 1] = '\0';
    return text;
}

void merd_session_publish(merd_session *s, uint64_t revision)
{
    json_t *summary = build_summary(s, revision);
    char *full = open_text(summary);
    json_t *brief = json_copy(summary);
    json_object_del(brief, "params");
    json_object_del(brief, "schedule");
    char *short_text = open_text(brief);
    json_decref(brief);
    mer_summary sum;
    mer_scene_summary(s->scene, &sum);
    pthread_mutex_lock(&s->state);
    json_decref(s->summary);
    free(s->summary_text);
    free(s->short_text);
    s->summary = summary;
    s->summary_text = full;
    s->short_text = short_text;
    s->revision = revision;
    s->internodes = sum.internodes;
    pthread_mutex_unlock(&s->state);
}

char *merd_session_summary_text(merd_session *s, bool full, uint64_t *revision)
{
    pthread_mutex_lock(&s->state);
    const char *base = full ? s->summary_text : s->short_text;
    char *text = NULL;
    if (base != NULL &&
        asprintf(&text, "%s,\"running\":{\"active\":%s,\"done\":%u,\"total\":%u}}\n", base,
                 s->running ? "true" : "false", s->done, s->total) < 0)
        text = NULL;
    *revision = s->revision;
    pthread_mutex_unlock(&s->state);
    return text;
}

json_t *merd_session_summary(merd_session *s, bool full)
{
    pthread_mutex_lock(&s->state);
    if (s->summary == NULL) { /* not loaded: all that is known without reading it */
        pthread_mutex_unlock(&s->state);
        return json_pack("{s:s, s:s}", "id", s->id, "state", "not loaded");
    }
    json_t *j = json_deep_copy(s->summary);
    json_t *running = json_pack("{s:b, s:i, s:i}", "active", s->running, "done",
                                (json_int_t)s->done, "total", (json_int_t)s->total);
    pthread_mutex_unlock(&s->state);
    json_object_set_new(j, "running", running);
    if (!full) {
        json_object_del(j, "params");
        json_object_del(j, "schedule");
    }
    return j;
}
