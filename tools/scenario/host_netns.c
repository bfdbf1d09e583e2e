/* host_netns: see host_netns.h. setns(2) is Linux's, hence _GNU_SOURCE
 * here alone (it would also declare glibc's daemon(3), a name the
 * daemons' shell uses). */
#define _GNU_SOURCE
#include "host_netns.h"
#include <errno.h>
#include <fcntl.h>
#include <sched.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

int host_netns_enter(const char *prefix, int host)
{
    char path[300];
    int fd, rc;
    if (!prefix)
        return 0;
    snprintf(path, sizeof path, "/var/run/netns/%s%d", prefix, host);
    fd = open(path, O_RDONLY | O_CLOEXEC);
    rc = fd >= 0 ? setns(fd, CLONE_NEWNET) : -1;
    if (rc != 0)
        fprintf(stderr, "formation: --host-netns: %s: %s\n", path, strerror(errno));
    if (fd >= 0)
        close(fd);
    return rc;
}
