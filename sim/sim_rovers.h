/* sim_rovers: extra hooks of the Pioneer model for benchmarks. */
#ifndef TANDEM_SIM_ROVERS_H
#define TANDEM_SIM_ROVERS_H

#include <stdint.h>

/* Sonar rays cast since the rover model was created. */
int64_t sim_rovers_rays_cast(void);

#endif
