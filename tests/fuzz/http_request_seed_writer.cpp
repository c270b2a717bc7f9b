// Writes the starting corpus of http_request_fuzz: requests for every route soltexd's HTTP
// endpoint has, with and without query parameters, and requests it refuses (bad ids, signed,
// huge and zero-padded coordinates, unknown parameters, bad methods), absolute-form targets,
// preflights, CONNECT, a body of unknown length and one that waits for 100 Continue.
//
//   http_request_seed_writer <corpus-dir>

#include <string>
#include <vector>

#include "seed_file.h"

namespace {

std::string request(const std::string& method, const std::string& target,
                    const std::string& body = "") {
  std::string text = method + " " + target + " HTTP/1.1\r\nHost: soltex\r\n";
  if (!body.empty()) text += "Content-Length: " + std::to_string(body.size()) + "\r\n";
  return text + "\r\n" + body;
}

std::vector<std::string> seeds() {
  const std::string id = "41a3e0c0279dd20b";
  const std::string brick = "/v1/textures/" + id + "/bricks/";
  // {"texture":{"marble":{}}} in base64url.
  const std::string spec = "eyJ0ZXh0dXJlIjp7Im1hcmJsZSI6e319fQ";
  return {
      request("POST", "/v1/textures", R"({"texture": {"marble": {}}})"),
      request("GET", "/v1/textures/" + id),
      request("GET", "/v1/textures/" + id + "?spec=" + spec),
      request("GET", brick + "0/0/0/0"),
      request("HEAD", brick + "3/1/2/3?codec=lz4"),
      request("GET", brick + "2/1/0/1?codec=raw&spec=" + spec),
      request("OPTIONS", brick + "0/0/0/0"),
      request("GET", brick + "0/-1/0/0"),
      request("GET", brick + "0/99999999999/0/0"),
      request("GET", brick + "0/007/0/0"),
      request("GET", brick + "0/0/0/0?codec=brotli"),
      request("GET", brick + "0/0/0/0?spec=@@"),
      request("GET", brick + "0/0/0/0?x=1&codec=zstd&codec=lz4"),
      request("GET", "/v1/textures/XYZ/bricks/0/0/0/0"),
      request("DELETE", "/v1/textures/" + id),
      request("GET", "/metrics"),
      request("GET", "http://soltex.example" + brick + "1/0/0/1?codec=raw"),
      request("OPTIONS", "/v1/textures/not-an-id/bricks/x"),
      request("OPTIONS", "*"),
      request("CONNECT", "soltex.example:443"),
      "POST /v1/textures HTTP/1.1\r\nHost: a\r\nTransfer-Encoding: gzip\r\n\r\n",
      "POST /v1/textures HTTP/1.1\r\nHost: a\r\nExpect: 100-continue\r\nContent-Length: "
      "2\r\n\r\n{}",
      brick + "1/2/3/4?spec=" + spec,
  };
}

}  // namespace

int main(int argc, char** argv) {
  return soltex::fuzz::seed_writer_main(argc, argv, {"corpus-dir"}, [](const auto& dirs) {
    int n = 0;
    for (const std::string& seed : seeds()) {
      soltex::fuzz::write_seed_file(dirs[0] / ("seed-" + std::to_string(n++)), seed);
    }
  });
}
