// SPDX-License-Identifier: LGPL-2.1-or-later
// The check that a port handed to another program is held by that program
// and by nothing else: a port another process holds (alone, or shared with
// SO_REUSEPORT) is not the program's, and a start on it is tried again on
// another port.
#include "held_ports.hpp"

#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <string>
#include <vector>

namespace ct = caustic::testing;
using caustic::testing::port_of;

namespace {

// A socket listening on 127.0.0.1:port (0: the kernel's pick), or -1.
int listen_on(int port, bool share = false) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int on = 1;
  if (share) ::setsockopt(fd, SOL_SOCKET, SO_REUSEPORT, &on, sizeof on);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(static_cast<uint16_t>(port));
  if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || ::listen(fd, 4) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

// Another process holding a listening socket of its own on a port: a
// child that keeps the socket this process made and then let go of.
class OtherHolder {
 public:
  explicit OtherHolder(bool share) {
    const int fd = listen_on(0, share);
    port_ = port_of(fd);
    pid_ = ::fork();
    if (pid_ == 0) {
      ::alarm(60);  // bounded even if the test dies before it is stopped
      for (;;) ::pause();
    }
    ::close(fd);
  }
  ~OtherHolder() {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }
  int port() const { return port_; }
  std::string pid() const { return std::to_string(pid_); }

 private:
  int port_ = 0;
  pid_t pid_ = -1;
};

}  // namespace

TEST(HeldPorts, APortIsHeldByTheProcessListeningOnItAlone) {
  OtherHolder other(false);  // first: its child would inherit a socket made before
  const int fd = listen_on(0);
  ASSERT_GE(fd, 0);
  const int port = port_of(fd);
  EXPECT_TRUE(ct::holds_port(std::to_string(::getpid()), port));
  EXPECT_TRUE(ct::holds_port(other.pid(), other.port()));
  EXPECT_FALSE(ct::holds_port(std::to_string(::getpid()), other.port()));
  EXPECT_FALSE(ct::holds_port(other.pid(), port));
  ::close(fd);
  EXPECT_FALSE(ct::holds_port(std::to_string(::getpid()), port)) << "nothing listens there now";
}

TEST(HeldPorts, APortSharedWithAnotherProcessIsNotHeld) {
  OtherHolder other(true);
  const int fd = listen_on(other.port(), true);
  ASSERT_GE(fd, 0) << "SO_REUSEPORT let no second listener bind";
  EXPECT_FALSE(ct::holds_port(std::to_string(::getpid()), other.port()));
  ::close(fd);
}

TEST(HeldPorts, AStartOnAPortAnotherProcessTookIsTriedAgainOnAnother) {
  OtherHolder other(false);
  std::vector<int> picked, tried;
  int fd = -1;
  const int port = ct::start_on_a_free_port(
      [&](int p) {
        tried.push_back(p);
        fd = listen_on(p);
        return fd >= 0 && ct::holds_port(std::to_string(::getpid()), p);
      },
      [&] {
        picked.push_back(picked.empty() ? other.port() : ct::free_port());
        return picked.back();
      });
  EXPECT_EQ(tried, picked);
  ASSERT_EQ(tried.size(), 2u) << "the taken port, then another";
  EXPECT_EQ(port, tried[1]);
  if (fd >= 0) ::close(fd);
}

TEST(HeldPorts, ThreeTakenPortsAreNoPort) {
  OtherHolder other(false);
  int tries = 0;
  EXPECT_EQ(ct::start_on_a_free_port(
                [&](int p) {
                  ++tries;
                  return ct::holds_port(std::to_string(::getpid()), p);
                },
                [&] { return other.port(); }),
            0);
  EXPECT_EQ(tries, 3);
}

TEST(HeldPorts, AChildThatExitsHoldsNothing) {
  OtherHolder other(false);
  ct::ChildProcess child({"/bin/sh", "-c", "exit 3"});
  EXPECT_FALSE(ct::comes_to_hold(child, other.port()));
}
