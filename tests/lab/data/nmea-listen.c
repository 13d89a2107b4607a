/* UDP listener of the panther-ops lab's NMEA driver stand-ins: the husarion/nmea-gps image
 * (tests/lab/nmea_image.py, nmea-gps-ros2-standin.sh) and the driver with launch_nmea_gps
 * (ros2-standin.sh). NOT the NMEA driver. It binds 0.0.0.0:PORT as nmea_socket_driver binds
 * its port (the real one binds its `ip` parameter, 10.15.20.2 on a Panther: the lab's robots
 * have other addresses), counts the datagrams (stdout: `docker logs` shows them) and ends at
 * once on SIGINT/SIGTERM.
 *
 * Like nmea_navsat_driver it "publishes" a sensor_msgs/NavSatFix on TOPIC for every GGA
 * sentence, by its rules (ros-drivers/nmea_navsat_driver@2.0.1, branch ros2, which the images
 * build; src/libnmea_navsat_driver/):
 *  - nodes/nmea_socket_driver.py: a datagram is decoded as ASCII, stripped, split at "\n";
 *    each piece is one sentence (the stand-in skips a datagram that is not ASCII text and a
 *    GGA with fewer than 12 fields, which stop the real node with an uncaught exception);
 *  - checksum_utils.py: exactly one '*'; the XOR of every character after the first up to
 *    the '*' equals the stripped text after it, in hex, either case;
 *  - parser.py: the sentence matches ^\$(GP|GN|GL|IN).*\*[0-9A-Fa-f]{2}$ (so a sentence that
 *    still ends in "\r" -- any but the last of a CRLF burst -- is dropped); fields split at
 *    ','; GGA: fix type int(field 6) and the UTC time's hh, mm, ss as ints (not numbers: the
 *    sentence is dropped), latitude ddmm.mmmm and longitude dddmm.mmmm (float, NaN when not a
 *    number; S and W negative), HDOP field 8, altitude field 9 plus geoid separation field 11;
 *  - driver.py: status by fix type 0 -> -1 (no fix), 1 -> 0 (fix), 2 -> 1 (SBAS), 4, 5, 9 ->
 *    2 (GBAS), any other -> -1; service 1 (GPS); covariance diagonal (hdop*e)^2, (hdop*e)^2,
 *    (2*hdop*2e)^2, e by fix type (0: 1000000, 1: 4.0, 2: 0.1, 4: 0.02, 5: 4.0, 9: 3.0, any
 *    other as 0), covariance type 1 (approximated), 0 (unknown) for fix type 0 and any other;
 *    stamp: now; RMC gives no fix (useRMC is false in every Husarion parameters file).
 *
 * The stand-in's stand-in for DDS discovery: on 127.0.0.1:11811 (TCP, the robot's network
 * namespace: both containers run with network_mode host) a client is held until the next
 * NavSatFix is published, then gets TOPIC on one line and the message as `ros2 topic echo`
 * prints it (rosidl_runtime_py's message_to_yaml, block style, then `---`), and is closed.
 * The driver's `ros2` stand-in reads it with busybox nc for `ros2 topic echo TOPIC`.
 * Usage: nmea-listen PORT [TOPIC [FRAME_ID]]   (default /fix and gps) */
#include <arpa/inet.h>
#include <ctype.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#define FIX_PORT 11811
#define MAX_CLIENTS 16

static volatile sig_atomic_t stop;
static int clients[MAX_CLIENTS], nclients;

static void on_signal(int sig) { (void)sig; stop = 1; }

static int py_space(char c) { return c == ' ' || (c >= '\t' && c <= '\r') || (c >= 0x1c && c <= 0x1f); }

/* Python's float(text), NaN where it raises (safe_float); `n` characters of `s` */
static double safe_float(const char *s, size_t n) {
    char buf[64], *end;
    if (n >= sizeof buf) return NAN;
    memcpy(buf, s, n);
    buf[n] = 0;
    double v = strtod(buf, &end);
    while (py_space(*end)) end++;
    return (end == buf || *end || strchr(buf, 'x') || strchr(buf, 'X')) ? NAN : v;
}

/* Python's int(text): 1 and *out when it is one */
static int py_int(const char *s, size_t n, long *out) {
    char buf[32], *end;
    if (n == 0 || n >= sizeof buf) return 0;
    memcpy(buf, s, n);
    buf[n] = 0;
    const char *p = buf;
    while (py_space(*p)) p++;
    if (*p == '+' || *p == '-') p++;
    if (*p < '0' || *p > '9') return 0;
    *out = strtol(buf, &end, 10);
    while (py_space(*end)) end++;
    return *end == 0;
}

/* a float as PyYAML writes it: repr() (shortest round trip; exponent below -4 or from 16),
 * '.0' added where repr has no '.'; .nan, .inf, -.inf */
static void yaml_float(char *out, size_t size, double v) {
    if (isnan(v)) { snprintf(out, size, ".nan"); return; }
    if (isinf(v)) { snprintf(out, size, v > 0 ? ".inf" : "-.inf"); return; }
    char e[40];
    int p = 1;
    for (; p < 17; p++) {
        snprintf(e, sizeof e, "%.*e", p - 1, v);
        if (strtod(e, NULL) == v) break;
    }
    snprintf(e, sizeof e, "%.*e", p - 1, v);
    int exp = atoi(strchr(e, 'e') + 1);
    if (exp >= -4 && exp < 16) {
        snprintf(out, size, "%.*f", p - 1 - exp > 0 ? p - 1 - exp : 0, v);
        if (!strchr(out, '.')) strncat(out, ".0", size - strlen(out) - 1);
    } else {
        char *m = strchr(e, 'e');
        *m = 0;
        snprintf(out, size, "%s%se%c%02d", e, strchr(e, '.') ? "" : ".0", exp < 0 ? '-' : '+', abs(exp));
    }
}

/* one sentence; 1 and the message in `msg` when it is a GGA the driver publishes */
static int gga(const char *line, const char *frame, char *msg, size_t size) {
    size_t n = strlen(line);
    const char *star = strchr(line, '*');
    if (!star || strchr(star + 1, '*')) return 0;
    unsigned sum = 0;
    for (const char *c = line + 1; c < star; c++) sum ^= (unsigned char)*c;
    const char *t = star + 1, *te = line + n;
    while (t < te && py_space(*t)) t++;
    while (te > t && py_space(te[-1])) te--;
    char want[8];
    snprintf(want, sizeof want, "%02X", sum);
    if ((size_t)(te - t) != strlen(want) || strncasecmp(t, want, te - t)) return 0;
    if (n < 6 || line[0] != '$' || line + n - 3 != star || !isxdigit((unsigned char)line[n - 2]) ||
        !isxdigit((unsigned char)line[n - 1]))
        return 0;
    if (strncmp(line + 1, "GP", 2) && strncmp(line + 1, "GN", 2) && strncmp(line + 1, "GL", 2) &&
        strncmp(line + 1, "IN", 2))
        return 0;
    const char *f[32];
    size_t len[32];
    int k = 0;
    for (const char *s = line;; k++) {
        if (k == 32) return 0;
        const char *comma = strchr(s, ',');
        f[k] = s;
        len[k] = comma ? (size_t)(comma - s) : strlen(s);
        if (!comma) { k++; break; }
        s = comma + 1;
    }
    if (len[0] != 6 || strncmp(f[0] + 3, "GGA", 3) || k < 12) return 0;
    long q, hms;
    if (!py_int(f[6], len[6], &q)) return 0;
    if (len[1] >= 5) /* hh, mm and ss all there: each an int */
        for (size_t i = 0; i < 6; i += 2)
            if (!py_int(f[1] + i, len[1] - i < 2 ? len[1] - i : 2, &hms)) return 0;
    size_t a = len[2] < 2 ? len[2] : 2, o = len[4] < 3 ? len[4] : 3;
    double lat = safe_float(f[2], a) + safe_float(f[2] + a, len[2] - a) / 60.0;
    double lon = safe_float(f[4], o) + safe_float(f[4] + o, len[4] - o) / 60.0;
    if (len[3] == 1 && f[3][0] == 'S') lat = -lat;
    if (len[5] == 1 && f[5][0] == 'W') lon = -lon;
    double alt = safe_float(f[9], len[9]) + safe_float(f[11], len[11]), hdop = safe_float(f[8], len[8]);
    int status = -1, cov_type = 0;
    double epe = 1000000;
    switch (q) {
        case 1: status = 0; cov_type = 1; epe = 4.0; break;
        case 2: status = 1; cov_type = 1; epe = 0.1; break;
        case 4: status = 2; cov_type = 1; epe = 0.02; break;
        case 5: status = 2; cov_type = 1; epe = 4.0; break;
        case 9: status = 2; cov_type = 1; epe = 3.0; break;
    }
    double cov[9] = {0};
    cov[0] = cov[4] = (hdop * epe) * (hdop * epe);
    cov[8] = (2 * hdop * epe * 2) * (2 * hdop * epe * 2);
    struct timespec now;
    clock_gettime(CLOCK_REALTIME, &now);
    char la[64], lo[64], al[64];
    yaml_float(la, sizeof la, lat);
    yaml_float(lo, sizeof lo, lon);
    yaml_float(al, sizeof al, alt);
    int w = snprintf(msg, size,
                     "header:\n  stamp:\n    sec: %ld\n    nanosec: %ld\n  frame_id: %s\nstatus:\n  status: %d\n"
                     "  service: 1\nlatitude: %s\nlongitude: %s\naltitude: %s\nposition_covariance:\n",
                     (long)now.tv_sec, now.tv_nsec, *frame ? frame : "''", status, la, lo, al);
    for (int i = 0; i < 9; i++) {
        char c[64];
        yaml_float(c, sizeof c, cov[i]);
        w += snprintf(msg + w, size - w, "- %s\n", c);
    }
    snprintf(msg + w, size - w, "position_covariance_type: %d\n---\n", cov_type);
    return 1;
}

static void publish(const char *topic, const char *msg) {
    for (int i = 0; i < nclients; i++) {
        dprintf(clients[i], "%s\n%s", topic, msg);
        close(clients[i]);
    }
    nclients = 0;
}

int main(int argc, char **argv) {
    int port = argc > 1 ? atoi(argv[1]) : 5000;
    const char *topic = argc > 2 ? argv[2] : "/fix", *frame = argc > 3 ? argv[3] : "gps";
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal; /* no SA_RESTART: poll returns on a signal */
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    signal(SIGPIPE, SIG_IGN);
    if (port < 1 || port > 65535) {
        fprintf(stderr, "[nmea-gps stand-in] bad port %s\n", argc > 1 ? argv[1] : "");
        return 2;
    }
    int fd = socket(AF_INET, SOCK_DGRAM, 0);
    struct sockaddr_in addr;
    memset(&addr, 0, sizeof addr);
    addr.sin_family = AF_INET;
    addr.sin_port = htons((unsigned short)port);
    addr.sin_addr.s_addr = htonl(INADDR_ANY);
    if (fd < 0 || bind(fd, (struct sockaddr *)&addr, sizeof addr) < 0) {
        perror("[nmea-gps stand-in] bind");
        return 1;
    }
    int one = 1, srv = socket(AF_INET, SOCK_STREAM, 0);
    addr.sin_port = htons(FIX_PORT);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    setsockopt(srv, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (srv < 0 || bind(srv, (struct sockaddr *)&addr, sizeof addr) < 0 || listen(srv, 8) < 0) {
        perror("[nmea-gps stand-in] 127.0.0.1:11811 (no fix served)");
        srv = -1;
    }
    printf("[nmea-gps stand-in] listening on udp 0.0.0.0:%d, publishing %s\n", port, topic);
    fflush(stdout);
    static char buf[65536], msg[2048];
    unsigned long count = 0;
    while (!stop) {
        struct pollfd p[2] = {{fd, POLLIN, 0}, {srv, POLLIN, 0}};
        if (poll(p, srv < 0 ? 1 : 2, -1) < 0) continue;
        if (srv >= 0 && (p[1].revents & POLLIN)) {
            int c = accept(srv, NULL, NULL);
            if (c >= 0) {
                if (nclients == MAX_CLIENTS) {
                    close(clients[0]);
                    memmove(clients, clients + 1, sizeof clients[0] * --nclients);
                }
                clients[nclients++] = c;
            }
        }
        if (!(p[0].revents & POLLIN)) continue;
        ssize_t got = recv(fd, buf, sizeof buf - 1, 0);
        if (got < 0) continue;
        buf[got] = 0;
        count++;
        if (count == 1 || count % 60 == 0) {
            printf("[nmea-gps stand-in] %lu datagrams\n", count);
            fflush(stdout);
        }
        int ascii = strlen(buf) == (size_t)got; /* ASCII text (a NUL: skipped too) */
        for (ssize_t i = 0; i < got; i++) ascii = ascii && (unsigned char)buf[i] < 128;
        if (!ascii) continue;
        char *s = buf, *e = buf + got;
        while (s < e && py_space(*s)) s++;
        while (e > s && py_space(e[-1])) *--e = 0;
        for (char *line = s; line && line < e;) {
            char *nl = strchr(line, '\n');
            if (nl) *nl = 0;
            if (gga(line, frame, msg, sizeof msg)) publish(topic, msg);
            line = nl ? nl + 1 : NULL;
        }
    }
    printf("[nmea-gps stand-in] signal received, %lu datagrams\n", count);
    return 0;
}
