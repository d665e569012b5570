/* The choice behind --budget-ms, kept apart from the timing so that tests
 * can give it timings. */
#include "scenes/budget.h"

int sb_budget_choose(const sb_budget_level* levels, int count, double budget_ms, bool* fits) {
    int best = -1, smallest = 0;
    for (int i = 0; i < count; i++) {
        if (levels[i].vertices < levels[smallest].vertices) smallest = i;
        if (levels[i].step_ms <= budget_ms && (best < 0 || levels[i].vertices > levels[best].vertices))
            best = i;
    }
    if (fits) *fits = best >= 0;
    return best >= 0 ? best : smallest;
}
