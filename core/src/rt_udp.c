/* Non-blocking IPv4 UDP endpoints for the HIL runner and the reference BCU. */
#define _POSIX_C_SOURCE 200809L
#include "railbrake/rb_rt.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <netinet/in.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

static rb_status address(struct sockaddr_in *a, const char *host, int port, rb_error *err)
{
    if (port < 0 || port > 65535) return rb_fail(err, RB_EINVAL, "port = %d: must lie in [0, 65535]", port);
    memset(a, 0, sizeof *a);
    a->sin_family = AF_INET;
    a->sin_port = htons((uint16_t)port);
    if (!host || inet_pton(AF_INET, host, &a->sin_addr) != 1)
        return rb_fail(err, RB_EINVAL, "host = '%s': must be a numeric IPv4 address", host ? host : "(null)");
    return RB_OK;
}

rb_status rb_udp_open(rb_udp *u, const char *bind_host, int bind_port, rb_error *err)
{
    struct sockaddr_in a;
    rb_status s = address(&a, bind_host, bind_port, err);
    if (s) return s;
    memset(u, 0, sizeof *u);
    u->fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (u->fd < 0) return rb_fail(err, RB_ESTATE, "socket: %s", strerror(errno));
    if (bind(u->fd, (struct sockaddr *)&a, sizeof a) != 0 || fcntl(u->fd, F_SETFL, O_NONBLOCK) != 0) {
        rb_fail(err, RB_ESTATE, "bind %s:%d: %s", bind_host, bind_port, strerror(errno));
        close(u->fd);
        u->fd = -1;
        return RB_ESTATE;
    }
    return RB_OK;
}

rb_status rb_udp_set_peer(rb_udp *u, const char *host, int port, rb_error *err)
{
    struct sockaddr_in a;
    rb_status s = address(&a, host, port, err);
    if (s) return s;
    memcpy(u->peer, &a, sizeof a);
    u->have_peer = 1;
    return RB_OK;
}

int rb_udp_local_port(const rb_udp *u)
{
    struct sockaddr_in a;
    socklen_t len = sizeof a;
    if (getsockname(u->fd, (struct sockaddr *)&a, &len) != 0) return -1;
    return ntohs(a.sin_port);
}

long rb_udp_send(rb_udp *u, const uint8_t *data, size_t size)
{
    if (u->fd < 0 || !u->have_peer) return -1;
    return (long)sendto(u->fd, data, size, 0, (const struct sockaddr *)u->peer, sizeof(struct sockaddr_in));
}

long rb_udp_recv_from(rb_udp *u, uint8_t *buf, size_t capacity, uint8_t from[16])
{
    if (u->fd < 0) return -1;
    struct sockaddr_in a;
    socklen_t len = sizeof a;
    memset(&a, 0, sizeof a);
    ssize_t n = recvfrom(u->fd, buf, capacity, MSG_TRUNC, (struct sockaddr *)&a, &len);
    if (n < 0) return (errno == EAGAIN || errno == EWOULDBLOCK) ? 0 : -1;
    memcpy(from, &a, sizeof a);
    return n == 0 ? RB_UDP_EMPTY : (long)n;   /* with MSG_TRUNC: the datagram's real size, > capacity if it was cut */
}

long rb_udp_recv(rb_udp *u, uint8_t *buf, size_t capacity)
{
    uint8_t from[16];
    long n = rb_udp_recv_from(u, buf, capacity, from);
    if (n == RB_UDP_EMPTY) n = 0;
    if (n > 0 && !u->have_peer) {
        memcpy(u->peer, from, sizeof from);
        u->have_peer = 1;
    }
    return n;
}

int rb_udp_same_address(const uint8_t a[16], const uint8_t b[16])
{
    struct sockaddr_in x, y;
    memcpy(&x, a, sizeof x);
    memcpy(&y, b, sizeof y);
    return x.sin_family == y.sin_family && x.sin_port == y.sin_port && x.sin_addr.s_addr == y.sin_addr.s_addr;
}

void rb_udp_format(const uint8_t address[16], char *text, size_t size)
{
    struct sockaddr_in a;
    char host[INET_ADDRSTRLEN] = "?";
    memcpy(&a, address, sizeof a);
    inet_ntop(AF_INET, &a.sin_addr, host, sizeof host);
    snprintf(text, size, "%s:%u", host, (unsigned)ntohs(a.sin_port));
}

long rb_udp_send_to(rb_udp *u, const uint8_t to[16], const uint8_t *data, size_t size)
{
    if (u->fd < 0) return -1;
    return (long)sendto(u->fd, data, size, 0, (const struct sockaddr *)to, sizeof(struct sockaddr_in));
}

void rb_udp_close(rb_udp *u)
{
    if (u->fd >= 0) close(u->fd);
    u->fd = -1;
}
