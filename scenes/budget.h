/* --budget-ms: pick the resolution whose measured step time fits. */
#ifndef SB_BUDGET_H
#define SB_BUDGET_H

#include <stdbool.h>
#include <stdint.h>

typedef struct sb_budget_level {
    uint32_t vertices; /* the model's size at this level */
    double step_ms;    /* measured time of one step */
} sb_budget_level;

/* The index of the level with the most vertices whose step_ms <= budget_ms;
 * when none fits, the level with the fewest vertices, and *fits (if not
 * NULL) is false. count >= 1. */
int sb_budget_choose(const sb_budget_level* levels, int count, double budget_ms, bool* fits);

#endif
