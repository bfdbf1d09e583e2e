/* host_netns: a child process moved into another network namespace
 * before it execs (tandem-scenario formation --host-netns): a rover host
 * that shares the machine but not its network stack, as another machine
 * on the bus would (tools/fleet-hosts.sh makes the namespaces). */
#ifndef TANDEM_HOST_NETNS_H
#define TANDEM_HOST_NETNS_H

/* Into the namespace /var/run/netns/<prefix><host>: 0 (nothing to do for
 * a NULL prefix), or -1 with the path and why on stderr. */
int host_netns_enter(const char *prefix, int host);

#endif
