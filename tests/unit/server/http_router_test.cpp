#include "http_router.h"

#include <gtest/gtest.h>

#include "base64url.h"

namespace soltex::server {
namespace {

constexpr const char* kId = "0123456789abcdef";

TEST(HttpRouter, RoutesEachResource) {
  const Route registration = route_request("POST", "/v1/textures");
  EXPECT_EQ(registration.kind, RouteKind::register_texture);

  const Route texture = route_request("GET", std::string("/v1/textures/") + kId);
  EXPECT_EQ(texture.kind, RouteKind::texture);
  EXPECT_EQ(texture.texture_id, 0x0123456789abcdefULL);

  const Route brick =
      route_request("HEAD", std::string("/v1/textures/") + kId + "/bricks/3/10/0/1073741824");
  ASSERT_EQ(brick.kind, RouteKind::brick) << brick.message;
  EXPECT_TRUE(brick.head);
  EXPECT_EQ(brick.level, 3u);
  EXPECT_EQ(brick.x, 10u);
  EXPECT_EQ(brick.y, 0u);
  EXPECT_EQ(brick.z, kMaxPathInteger);
  EXPECT_EQ(brick.codec, Codec::zstd);

  const Route query = route_request(
      "GET", std::string("/v1/textures/") + kId + "/bricks/0/0/0/0?spec=e30&codec=lz4");
  ASSERT_EQ(query.kind, RouteKind::brick) << query.message;
  EXPECT_EQ(query.codec, Codec::lz4);
  EXPECT_EQ(query.spec, "e30");

  const Route preflight = route_request("OPTIONS", "/v1/textures");
  EXPECT_EQ(preflight.kind, RouteKind::preflight);
  EXPECT_EQ(preflight.allow, "POST, OPTIONS");

  // Absolute form names the same routes; its empty path is "/".
  const Route absolute = route_request(
      "GET", std::string("HTTP://soltex.example:8080/v1/textures/") + kId + "/bricks/1/2/3/4");
  ASSERT_EQ(absolute.kind, RouteKind::brick) << absolute.message;
  EXPECT_EQ(absolute.z, 4u);
  const Route root = route_request("GET", "http://soltex.example?codec=raw");
  EXPECT_EQ(root.status, 404u);
  EXPECT_NE(root.message.find("no resource at '/'"), std::string::npos) << root.message;
}

TEST(HttpRouter, RefusesWithTheStatusAndWhatWasWrong) {
  const std::string brick = std::string("/v1/textures/") + kId + "/bricks/";
  const struct {
    const char* method;
    std::string target;
    unsigned status;
    const char* names;
  } cases[] = {
      {"GET", "/", 404, "no resource at '/'"},
      {"GET", "/v1/textures/" + std::string(kId) + "/bricks/1/2/3", 404, "no resource"},
      {"GET", "/v1/textures/0123456789ABCDEF", 400, "texture id '0123456789ABCDEF'"},
      {"GET", "/v1/textures/0123", 400, "16 lower-case hex digits"},
      {"GET", brick + "0/-1/0/0", 400, "x = '-1'"},
      {"GET", brick + "0/0/+1/0", 400, "y = '+1'"},
      {"GET", brick + "0/0/0/1073741825", 400, "z = '1073741825'"},
      {"GET", brick + "00/0/0/0", 400, "level = '00'"},
      {"GET", brick + "/0/0/0", 400, "level = ''"},
      {"GET", brick + "0/0/0/0?codec=gzip", 400, "codec = 'gzip'"},
      {"GET", brick + "0/0/0/0?codec=lz4&codec=raw", 400, "given twice"},
      {"GET", brick + "0/0/0/0?spec=a+b", 400, "base64url"},
      {"GET", brick + "0/0/0/0?spec=" + std::string(kMaxSpecParameterBytes + 1, 'A'), 414,
       "at most 12288"},
      {"GET", brick + "0/0/0/0?cachebust=1", 400, "unknown query parameter 'cachebust'"},
      {"POST", brick + "0/0/0/0", 405, "'POST' is not allowed here; use GET, HEAD"},
      {"GET", "/v1/textures", 405, "use POST"},
      {"POST", "/v1/textures?codec=lz4", 400, "takes no query parameters"},
  };
  for (const auto& c : cases) {
    const Route route = route_request(c.method, c.target);
    EXPECT_EQ(route.kind, RouteKind::refused) << c.target;
    EXPECT_EQ(route.status, c.status) << c.target;
    EXPECT_NE(route.message.find(c.names), std::string::npos) << c.target << ": " << route.message;
    if (route.status == 405) EXPECT_FALSE(route.allow.empty());
  }
}

TEST(Base64Url, RoundTripsWithOneSpellingPerByteString) {
  const std::string all = [] {
    std::string bytes;
    for (int i = 0; i < 256; ++i) bytes += static_cast<char>(i);
    return bytes;
  }();
  for (std::size_t n = 0; n <= all.size(); n += 7) {
    const std::string text = base64url_encode(all.substr(0, n));
    EXPECT_EQ(text.find_first_of("+/="), std::string::npos);
    EXPECT_EQ(base64url_decode(text), all.substr(0, n));
  }
  EXPECT_EQ(base64url_encode("{}"), "e30");
  EXPECT_EQ(base64url_decode("e30"), "{}");
  EXPECT_EQ(base64url_decode("e31"), std::nullopt);   // bits left over must be zero
  EXPECT_EQ(base64url_decode("e30="), std::nullopt);  // no padding
  EXPECT_EQ(base64url_decode("e"), std::nullopt);     // no length 1 mod 4
  EXPECT_EQ(base64url_decode("a/b+"), std::nullopt);  // the other alphabet
}

}  // namespace
}  // namespace soltex::server
