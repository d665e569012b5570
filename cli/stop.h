/* When a run stops (`stop.*` keys), after the Spring Systems demo
 * application: when the total kinetic energy falls below
 * stop.kinetic_energy (J; 0 = never), but not before stop.min_time (s);
 * at the latest at stop.max_time (s, the watchdog; 0 = the duration) or at
 * the duration, whichever comes first. The run says which ended it (a
 * run without stop keys just ends at its duration). */
#ifndef SB_SCENE_STOP_H
#define SB_SCENE_STOP_H

#include "scenes/scene.h"

#include <stdio.h>

typedef enum sb_stop_reason {
    SB_STOP_RUNNING = 0,
    SB_STOP_KINETIC_ENERGY, /* the kinetic energy fell below stop.kinetic_energy */
    SB_STOP_WATCHDOG,       /* stop.max_time came first, or the end came with a kinetic-energy stop pending */
    SB_STOP_DURATION        /* the duration, with no stop condition set */
} sb_stop_reason;

typedef struct sb_stop {
    double kinetic_energy, min_time, max_time, duration;
    sb_stop_reason reason;
    double time, kinetic; /* when it stopped and the kinetic energy then */
} sb_stop;

/* The scene's stop keys (checked by sb_scene_validate). */
sb_stop sb_stop_from_scene(const sb_scene* scene);
/* s: when the run ends at the latest, min(duration, max_time). */
double sb_stop_end(const sb_stop* stop);
/* Whether the kinetic energy stop is armed at `time` (stop.kinetic_energy
 * set, min_time reached): the run asks the solver for its energies after a
 * step only then, since that settles the forces a lazy step (pbd, xpbd,
 * vbd, fast implicit Euler) left for later, a force pass a step. */
bool sb_stop_watches(const sb_stop* stop, double time);
/* After a step: true (and the reason kept) when the kinetic energy stop fires. */
bool sb_stop_after_step(sb_stop* stop, double time, double kinetic);
/* The run reached sb_stop_end: the watchdog or the duration. */
void sb_stop_at_end(sb_stop* stop, double time, double kinetic);
/* "stopped at t = … s: …" and a newline. */
void sb_stop_print(const sb_stop* stop, FILE* stream);

#endif
