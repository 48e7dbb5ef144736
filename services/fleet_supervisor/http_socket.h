// Small socket helpers shared by the supervisor's connection front, its workers and its live
// stream hub: non-blocking mode, sending with a deadline, and the short error answers the front
// gives without involving a handler.
#pragma once

#include <sys/socket.h>

#include <chrono>
#include <string>
#include <string_view>

namespace fleetloc::fleet_supervisor {

using SteadyClock = std::chrono::steady_clock;

// Puts `fd` in non-blocking mode (and close-on-exec); false on failure.
bool SetNonBlocking(int fd);

// Sends all of `data` on the non-blocking `fd`, waiting (poll) until `deadline` for room; false
// when the peer is gone or the deadline passed.
bool SendBefore(int fd, std::string_view data, SteadyClock::time_point deadline);

// A complete HTTP/1.1 response with a JSON {"error": message} body and "Connection: close".
std::string ErrorResponse(int status, std::string_view message);

// The reason phrase of the statuses the front answers itself.
const char* ReasonPhrase(int status);

// Best effort, never waiting: sends ErrorResponse and closes `fd`.
void AnswerAndClose(int fd, int status, std::string_view message);

// Shuts down and closes `fd` (ignoring errors).
void CloseSocket(int fd);

// The numeric address and port of a socket address (IPv4 or IPv6; "" and 0 for others).
void AddressOf(const sockaddr_storage& address, std::string& ip, int& port);

// The peer's numeric address ("" when unknown).
std::string PeerAddress(int fd);

}  // namespace fleetloc::fleet_supervisor
