/* sim_rovers: extra hooks of the Pioneer model for benchmarks. */
#ifndef TANDEM_SIM_ROVERS_H
#define TANDEM_SIM_ROVERS_H

#include <stdint.h>

/* Sonar rays cast since the rover model was created. */
int64_t sim_rovers_rays_cast(void);

/* Hold command (V, w) for robot id as if received at sim step `step`
 * (benchmarks drive the robots without LCM). -1 unknown id. */
int sim_rovers_set_command(int32_t id, double v_mps, double w_radps, int64_t step);

#endif
