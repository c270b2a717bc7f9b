#include "soltex/net/loopback_address.h"

#include <gtest/gtest.h>

namespace soltex::net {
namespace {

TEST(LoopbackAddress, ThisMachineInEveryFormAGrpcTargetTakes) {
  for (const char* target :
       {"127.0.0.1:7447", "127.1.2.3:80", "localhost:7447", "LOCALHOST", "app.localhost:1",
        "[::1]:7447", "::1", "[::ffff:127.0.0.1]:7447", "ipv4:127.0.0.1:7447",
        "ipv4:127.0.0.1:1,127.0.0.2:2", "ipv6:[::1]:7447", "dns:///localhost:7447",
        "dns:localhost:7447", "dns://8.8.8.8/localhost:7447", "unix:/tmp/soltexd.sock",
        "unix-abstract:soltexd"}) {
    EXPECT_TRUE(is_loopback_address(target)) << target;
  }
}

TEST(LoopbackAddress, AnyOtherHostIsNot) {
  for (const char* target :
       {"10.0.0.5:7447", "192.168.1.2", "example.com:7447", "localhost.example.com:7447",
        "[2001:db8::1]:7447", "2001:db8::1", "[::ffff:10.0.0.1]:1", "ipv4:127.0.0.1:1,10.0.0.1:2",
        "dns:///example.com:7447", "dns://8.8.8.8", "128.0.0.1:7447", "", ":7447"}) {
    EXPECT_FALSE(is_loopback_address(target)) << target;
  }
}

}  // namespace
}  // namespace soltex::net
