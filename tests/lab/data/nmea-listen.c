/* UDP listener of the panther-ops lab's nmea-gps stand-in image (tests/lab/nmea_image.py).
 * NOT the NMEA driver: it binds 0.0.0.0:PORT as nmea_socket_driver binds its port, counts the
 * datagrams (printed on stdout: `docker logs` shows them) and ends at once on SIGINT/SIGTERM.
 * Usage: nmea-listen PORT */
#include <arpa/inet.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

static volatile sig_atomic_t stop;

static void on_signal(int sig) { (void)sig; stop = 1; }

int main(int argc, char **argv) {
    int port = argc > 1 ? atoi(argv[1]) : 5000;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal; /* no SA_RESTART: recv returns on a signal */
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
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
    printf("[nmea-gps stand-in] listening on udp 0.0.0.0:%d\n", port);
    fflush(stdout);
    static char buf[65536];
    unsigned long count = 0;
    while (!stop) {
        if (recv(fd, buf, sizeof buf, 0) < 0)
            continue;
        count++;
        if (count == 1 || count % 60 == 0) {
            printf("[nmea-gps stand-in] %lu datagrams\n", count);
            fflush(stdout);
        }
    }
    printf("[nmea-gps stand-in] signal received, %lu datagrams\n", count);
    return 0;
}
