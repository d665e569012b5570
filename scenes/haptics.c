/* The scene's haptics (scenes/haptics.h): the keys checked, the device
 * opened, the servo run beside the simulation, haptics.csv written by the
 * simulation thread from the servo's log (the servo itself never writes a
 * file). */
#define _POSIX_C_SOURCE 200809L
#include "scenes/haptics.h"
#include "scenes/suggest.h"
#include "common/error.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { DRAIN_BATCH = 256 };

static bool tool_wanted(const sb_scene* scene) { return sb_scene_string(scene, SB_KEY_HAPTICS_TOOL)[0] != '\0'; }

sb_status sb_scene_haptics_check(const sb_scene* scene, sb_error* err) {
    const char* kind = sb_scene_string(scene, SB_KEY_HAPTICS_DEVICE);
    char near[96];
    if (!sb_haptic_device_kind_known(kind))
        return sb_scene_fail(scene, SB_KEY_HAPTICS_DEVICE, err,
                             "'haptics.device': expected none, scripted, udp or mouse, got '%s'%s", kind,
                             sb_suggest_hint(kind, "none, scripted, udp, mouse", near, sizeof near));
    if (strcmp(kind, "scripted") == 0 && sb_scene_string(scene, SB_KEY_HAPTICS_FILE)[0] == '\0')
        return sb_scene_fail(scene, SB_KEY_HAPTICS_DEVICE, err, "'haptics.device: scripted' needs haptics.file");
    int64_t port = sb_scene_integer(scene, SB_KEY_HAPTICS_PORT);
    if (port < 1 || port > 65535)
        return sb_scene_fail(scene, SB_KEY_HAPTICS_PORT, err, "'haptics.port' must be from 1 to 65535, got %lld",
                             (long long)port);
    if (strcmp(kind, "none") != 0 && !tool_wanted(scene))
        return sb_scene_fail(scene, SB_KEY_HAPTICS_DEVICE, err,
                             "'haptics.device: %s' needs haptics.tool (a collider's name)", kind);
    sb_haptics_def def = sb_default_haptics_def();
    def.rate = sb_scene_number(scene, SB_KEY_HAPTICS_RATE);
    def.stiffness = sb_scene_number(scene, SB_KEY_HAPTICS_COUPLING_STIFFNESS);
    def.damping = sb_scene_number(scene, SB_KEY_HAPTICS_COUPLING_DAMPING);
    def.max_force = sb_scene_number(scene, SB_KEY_HAPTICS_MAX_FORCE);
    def.workspace = sb_scene_number(scene, SB_KEY_HAPTICS_WORKSPACE);
    def.hand_speed = sb_scene_number(scene, SB_KEY_HAPTICS_HAND_SPEED);
    /* The library checks the numbers; its message is given the place of the key it names. */
    static const struct {
        const char* word;
        sb_scene_key key;
    } blame[] = {{"rate", SB_KEY_HAPTICS_RATE},
                 {"stiffness", SB_KEY_HAPTICS_COUPLING_STIFFNESS},
                 {"damping", SB_KEY_HAPTICS_COUPLING_DAMPING},
                 {"max_force", SB_KEY_HAPTICS_MAX_FORCE},
                 {"workspace", SB_KEY_HAPTICS_WORKSPACE},
                 {"hand_speed", SB_KEY_HAPTICS_HAND_SPEED}};
    sb_error check;
    sb_haptic_device* none = sb_haptic_device_open(&(sb_haptic_device_def){.kind = "none"}, err);
    sb_collider_def point = sb_default_collider_def();
    sb_collider* probe = sb_collider_create(&point, err);
    sb_haptics* h = none && probe ? sb_haptics_create(&def, none, probe, 0, &check) : NULL;
    bool ok = h != NULL;
    sb_haptics_destroy(h);
    sb_haptic_device_close(none);
    sb_collider_destroy(probe);
    if (ok) return SB_OK;
    for (size_t i = 0; i < sizeof blame / sizeof blame[0]; i++)
        if (strstr(check.message, blame[i].word))
            return sb_scene_fail(scene, blame[i].key, err, "%s", check.message + strlen("haptics: "));
    return sb_error_set(err, SB_ERR_INVALID, "%s", check.message);
}

static sb_status find_tool(const sb_scene* scene, const sb_scene_colliders* colliders, uint32_t* index, sb_error* err) {
    const char* name = sb_scene_string(scene, SB_KEY_HAPTICS_TOOL);
    for (uint32_t c = 0; c < colliders->count; c++) {
        if (strcmp(colliders->entries[c].name, name) != 0) continue;
        const sb_collider_def* def = &colliders->entries[c].def;
        if (def->shape == SB_COLLIDER_PLANE || def->mass > 0)
            return sb_scene_fail(scene, SB_KEY_HAPTICS_TOOL, err,
                                 "'haptics.tool': collider '%s' cannot be a tool (a plane or a dynamic body)", name);
        *index = c;
        return SB_OK;
    }
    return sb_scene_fail(scene, SB_KEY_HAPTICS_TOOL, err, "'haptics.tool': no collider is named '%s'", name);
}

sb_status sb_scene_haptics_create(sb_scene_haptics* h, const sb_scene* scene, const sb_scene_colliders* colliders,
                                  sb_error* err) {
    *h = (sb_scene_haptics){0};
    if (!tool_wanted(scene)) return SB_OK;
    uint32_t index = 0;
    sb_status status = find_tool(scene, colliders, &index, err);
    if (status != SB_OK) return status;
    char* file = sb_scene_path(scene, SB_KEY_HAPTICS_FILE);
    sb_haptic_device_def device = sb_default_haptic_device_def();
    device.kind = sb_scene_string(scene, SB_KEY_HAPTICS_DEVICE);
    device.file = file;
    device.port = (int)sb_scene_integer(scene, SB_KEY_HAPTICS_PORT);
    h->device = sb_haptic_device_open(&device, err);
    free(file);
    if (!h->device) return sb_error_prefix(err, SB_ERR_INVALID, sb_scene_where(scene, SB_KEY_HAPTICS_DEVICE));
    sb_haptics_def def = sb_default_haptics_def();
    def.rate = sb_scene_number(scene, SB_KEY_HAPTICS_RATE);
    def.stiffness = sb_scene_number(scene, SB_KEY_HAPTICS_COUPLING_STIFFNESS);
    def.damping = sb_scene_number(scene, SB_KEY_HAPTICS_COUPLING_DAMPING);
    def.max_force = sb_scene_number(scene, SB_KEY_HAPTICS_MAX_FORCE);
    def.workspace = sb_scene_number(scene, SB_KEY_HAPTICS_WORKSPACE);
    def.hand_speed = sb_scene_number(scene, SB_KEY_HAPTICS_HAND_SPEED);
    h->haptics = sb_haptics_create(&def, h->device, colliders->colliders[index], index, err);
    if (!h->haptics) return SB_ERR_INVALID;
    h->paced = sb_scene_bool(scene, SB_KEY_HAPTICS_REALTIME);
    h->rate = def.rate;
    h->enabled = true;
    return SB_OK;
}

sb_status sb_scene_haptics_start(sb_scene_haptics* h, const char* path, sb_error* err) {
    if (!h->enabled) return SB_OK;
    if (!(h->csv = fopen(path, "w"))) return sb_error_at(err, SB_ERR_IO, path, 0, "cannot write: %s", strerror(errno));
    fprintf(h->csv, "time,device_x,device_y,device_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,step\n");
    bool realtime;
    sb_status status = sb_haptics_start(h->haptics, &realtime, err);
    if (status != SB_OK) return status;
    h->wall_start = sb_haptics_clock(h->haptics);
    printf("softbond: haptics: servo thread at %g Hz, %s\n", h->rate,
           realtime ? "real-time priority (SCHED_FIFO)" : "normal priority (SCHED_FIFO was refused)");
    fflush(stdout);
    return SB_OK;
}

static void sleep_until(double seconds_on_servo_clock, const sb_haptics* haptics) {
    double wait = seconds_on_servo_clock - sb_haptics_clock(haptics);
    if (wait <= 0) return;
    struct timespec t = {.tv_sec = (time_t)wait, .tv_nsec = (long)((wait - floor(wait)) * 1e9)};
    while (nanosleep(&t, &t) == -1 && errno == EINTR) {
    }
}

void sb_scene_haptics_before_step(sb_scene_haptics* h, const sb_solver* solver) {
    if (!h->enabled) return;
    if (h->paced) sleep_until(h->wall_start + sb_solver_time(solver), h->haptics);
    sb_haptics_drive(h->haptics);
}

static void say_faults(sb_scene_haptics* h) {
    uint32_t faults = sb_haptics_faults(h->haptics);
    if (faults && faults != h->faults)
        fprintf(stderr, "softbond: haptics: the force ramps to zero:%s%s%s%s\n",
                faults & SB_HAPTIC_FAULT_STALL ? " the simulation stalled" : "",
                faults & SB_HAPTIC_FAULT_NONFINITE ? " a value was not finite" : "",
                faults & SB_HAPTIC_FAULT_POSE
                    ? " a pose no hand gave (outside haptics.workspace, faster than haptics.hand_speed, or not a unit quaternion)"
                    : "",
                faults & SB_HAPTIC_FAULT_DEVICE ? " the device failed" : "");
    h->faults = faults;
}

static sb_status write_ticks(sb_scene_haptics* h, sb_error* err) {
    sb_haptic_tick ticks[DRAIN_BATCH];
    size_t n;
    while ((n = sb_haptics_drain(h->haptics, ticks, DRAIN_BATCH)) > 0)
        for (size_t i = 0; i < n; i++) {
            const sb_haptic_tick* t = &ticks[i];
            fprintf(h->csv, "%.6f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.6g,%.6g,%.6g,%llu\n", t->time, t->device[0],
                    t->device[1], t->device[2], t->proxy[0], t->proxy[1], t->proxy[2], t->force[0], t->force[1],
                    t->force[2], (unsigned long long)t->step);
        }
    return ferror(h->csv) ? sb_error_set(err, SB_ERR_IO, "haptics.csv: write failed") : SB_OK;
}

sb_status sb_scene_haptics_after_step(sb_scene_haptics* h, const sb_solver* solver, sb_error* err) {
    if (!h->enabled) return SB_OK;
    sb_haptics_sense(h->haptics, solver, sb_haptics_clock(h->haptics));
    say_faults(h);
    return write_ticks(h, err);
}

sb_status sb_scene_haptics_finish(sb_scene_haptics* h, sb_error* err) {
    if (!h->enabled || !h->csv) return SB_OK;
    sb_haptics_stop(h->haptics);
    sb_status status = write_ticks(h, err);
    if (fclose(h->csv) != 0 && status == SB_OK) status = sb_error_set(err, SB_ERR_IO, "haptics.csv: write failed");
    h->csv = NULL;
    sb_haptics_stats s = sb_haptics_statistics(h->haptics);
    printf("softbond: haptics: %llu ticks, period median %.3f ms, p99 %.3f ms, max %.3f ms; contact model age "
           "median %.2f ms, p99 %.2f ms; %llu ticks not logged\n",
           (unsigned long long)s.ticks, 1e3 * s.period_median, 1e3 * s.period_p99, 1e3 * s.period_max,
           1e3 * s.age_median, 1e3 * s.age_p99, (unsigned long long)sb_haptics_dropped(h->haptics));
    return status;
}

void sb_scene_haptics_free(sb_scene_haptics* h) {
    if (h->csv) fclose(h->csv);
    sb_haptics_destroy(h->haptics);
    sb_haptic_device_close(h->device);
    *h = (sb_scene_haptics){0};
}
