#pragma once
// cpp-httplib binds with SO_REUSEPORT by default, so a second server on a taken port "succeeds"
// and the kernel splits the connections between the two. Our servers (the play page, `mtg
// view`) keep SO_REUSEADDR (a restart does not wait for TIME_WAIT) and refuse a taken port.

#include <httplib.h>
#include <sys/socket.h>

namespace mtg::web {

inline void bind_exclusively(httplib::Server& server) {
  server.set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
}

}  // namespace mtg::web
