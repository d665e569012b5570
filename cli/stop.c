/* The run's stop conditions (see stop.h). The kinetic energy is the
 * solver's, summed over the free vertices at the end of every step; the run
 * asks for it after each step only while the stop is armed (from min_time
 * on, stop.kinetic_energy set): reading the energies settles the forces that
 * pbd, xpbd, vbd and the fast implicit Euler leave for later, a force pass. */
#include "cli/stop.h"

sb_stop sb_stop_from_scene(const sb_scene* scene) {
    return (sb_stop){.kinetic_energy = sb_scene_number(scene, SB_KEY_STOP_KINETIC_ENERGY),
                     .min_time = sb_scene_number(scene, SB_KEY_STOP_MIN_TIME),
                     .max_time = sb_scene_number(scene, SB_KEY_STOP_MAX_TIME),
                     .duration = sb_scene_number(scene, SB_KEY_DURATION)};
}

double sb_stop_end(const sb_stop* stop) {
    return stop->max_time > 0.0 && stop->max_time < stop->duration ? stop->max_time : stop->duration;
}

static void sb_stop_set(sb_stop* stop, sb_stop_reason reason, double time, double kinetic) {
    stop->reason = reason;
    stop->time = time;
    stop->kinetic = kinetic;
}

bool sb_stop_watches(const sb_stop* stop, double time) { return stop->kinetic_energy > 0.0 && time >= stop->min_time; }

bool sb_stop_after_step(sb_stop* stop, double time, double kinetic) {
    if (!sb_stop_watches(stop, time) || !(kinetic < stop->kinetic_energy)) return false;
    sb_stop_set(stop, SB_STOP_KINETIC_ENERGY, time, kinetic);
    return true;
}

void sb_stop_at_end(sb_stop* stop, double time, double kinetic) {
    bool watchdog = stop->kinetic_energy > 0.0 || sb_stop_end(stop) < stop->duration;
    sb_stop_set(stop, watchdog ? SB_STOP_WATCHDOG : SB_STOP_DURATION, time, kinetic);
}

void sb_stop_print(const sb_stop* stop, FILE* stream) {
    switch (stop->reason) {
    case SB_STOP_KINETIC_ENERGY:
        fprintf(stream, "softbond: stopped at t = %.6g s: kinetic energy %.6g J below stop.kinetic_energy (%g J)\n",
                stop->time, stop->kinetic, stop->kinetic_energy);
        break;
    case SB_STOP_WATCHDOG:
        fprintf(stream, "softbond: stopped at t = %.6g s: watchdog (%s %g s reached", stop->time,
                sb_stop_end(stop) < stop->duration ? "stop.max_time" : "the duration", sb_stop_end(stop));
        if (stop->kinetic_energy > 0.0)
            fprintf(stream, "; kinetic energy %.6g J still above stop.kinetic_energy (%g J)", stop->kinetic,
                    stop->kinetic_energy);
        fprintf(stream, ")\n");
        break;
    case SB_STOP_DURATION: /* said only when the scene set a stop key: a plain run just ends */
        if (stop->max_time > 0.0) fprintf(stream, "softbond: stopped at t = %.6g s: duration reached\n", stop->time);
        break;
    case SB_STOP_RUNNING: break;
    }
}
