// For tests: 8-bit gray frames sent as UDP datagrams to 127.0.0.1, one frame a datagram, for a
// GStreamer pipeline that reads them with udpsrc (UdpGrayPipeline) — a live source the test can
// stop (the pipeline stalls) and resume.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <opencv2/core.hpp>
#include <string>

namespace fleetloc::camera_io::testing {

class UdpFrameSender {
 public:
  UdpFrameSender() : socket_(::socket(AF_INET, SOCK_DGRAM, 0)) {}
  ~UdpFrameSender() {
    if (socket_ >= 0) ::close(socket_);
  }
  UdpFrameSender(const UdpFrameSender&) = delete;
  UdpFrameSender& operator=(const UdpFrameSender&) = delete;

  // A UDP port on 127.0.0.1 that was free a moment ago (0 when none could be found).
  static int FreePort() {
    const int s = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = 0;
    socklen_t size = sizeof a;
    int port = 0;
    if (s >= 0 && ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
        ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &size) == 0)
      port = ntohs(a.sin_port);
    if (s >= 0) ::close(s);
    return port;
  }
  // Sends a continuous CV_8UC1 frame; false when the datagram could not be sent.
  bool Send(const cv::Mat& gray, int port) const {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<uint16_t>(port));
    const size_t bytes = gray.total() * gray.elemSize();
    return ::sendto(socket_, gray.data, bytes, 0, reinterpret_cast<sockaddr*>(&a), sizeof a) ==
           static_cast<ssize_t>(bytes);
  }

 private:
  int socket_;
};

// A pipeline reading width×height GRAY8 frames from UDP `port` into an appsink.
inline std::string UdpGrayPipeline(int port, int width, int height) {
  return "udpsrc address=127.0.0.1 port=" + std::to_string(port) +
         " caps=\"video/x-raw,format=GRAY8,width=" + std::to_string(width) +
         ",height=" + std::to_string(height) + ",framerate=0/1\" ! appsink sync=false";
}

}  // namespace fleetloc::camera_io::testing
