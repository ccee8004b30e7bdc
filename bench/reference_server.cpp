/* The plainest libmodbus TCP server, the reference tiltgate's Modbus TCP side is measured
 * against (scripts/bench): a static mapping of 200 holding and 200 input registers, nothing else
 * to do, and a select() loop over every client with modbus_receive / modbus_reply, as
 * libmodbus's own tests/bandwidth-server-many-up.c.
 *
 * Usage: bench_reference_server PORT   (listens on 127.0.0.1 only; SIGTERM or SIGINT ends it) */
#include <errno.h>
#include <modbus.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/select.h>
#include <unistd.h>

#define REGISTERS 200

static volatile sig_atomic_t stopping = 0;

static void stop(int signal_number) {
  (void)signal_number;
  stopping = 1;
}

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: %s PORT\n", argv[0]);
    return 2;
  }
  const int port = atoi(argv[1]);
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", port);
  modbus_mapping_t* mapping = modbus_mapping_new(0, 0, REGISTERS, REGISTERS);
  if (ctx == NULL || mapping == NULL) {
    fprintf(stderr, "libmodbus: %s\n", modbus_strerror(errno));
    return 1;
  }
  for (int i = 0; i < REGISTERS; ++i) {
    mapping->tab_registers[i] = (uint16_t)(1000 + i);
    mapping->tab_input_registers[i] = (uint16_t)(2000 + i);
  }
  int server = modbus_tcp_listen(ctx, 1024);
  if (server < 0) {
    fprintf(stderr, "listen on port %d: %s\n", port, modbus_strerror(errno));
    return 1;
  }
  struct sigaction action {};
  action.sa_handler = stop;
  sigaction(SIGTERM, &action, NULL);
  sigaction(SIGINT, &action, NULL);
  printf("listening on 127.0.0.1:%d\n", port);
  fflush(stdout);

  fd_set clients;
  FD_ZERO(&clients);
  FD_SET(server, &clients);
  int max_fd = server;
  uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];
  while (!stopping) {
    fd_set ready = clients;
    if (select(max_fd + 1, &ready, NULL, NULL, NULL) < 0) {
      if (errno == EINTR) continue;
      perror("select");
      break;
    }
    for (int fd = 0; fd <= max_fd; ++fd) {
      if (!FD_ISSET(fd, &ready)) continue;
      if (fd == server) {
        const int client = modbus_tcp_accept(ctx, &server);
        if (client >= 0 && client < FD_SETSIZE) {
          FD_SET(client, &clients);
          if (client > max_fd) max_fd = client;
        } else if (client >= 0) {
          close(client);
        }
        continue;
      }
      modbus_set_socket(ctx, fd);
      const int length = modbus_receive(ctx, query);
      if (length > 0) {
        modbus_reply(ctx, query, length, mapping);
      } else if (length < 0) {
        close(fd);
        FD_CLR(fd, &clients);
      }
    }
  }
  modbus_mapping_free(mapping);
  modbus_close(ctx);
  modbus_free(ctx);
  return 0;
}
