#include "http_request_handler.h"

#include <xxhash.h>

#include <boost/beast/http/field.hpp>
#include <boost/beast/version.hpp>
#include <cstdio>
#include <ctime>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "base64url.h"
#include "http_message_checks.h"
#include "registration_json.h"
#include "soltex/common/texture_id.h"
#include "texture_registration.h"

namespace soltex::server {
namespace {

namespace http = boost::beast::http;

// A request answered with an error status; thrown inside the handler, caught once.
struct HttpError {
  unsigned status;
  std::string message;
};

constexpr const char* kImmutable = "public, max-age=31536000, immutable";
// With tokens required, a shared cache must not hand bricks to callers nobody checked.
constexpr const char* kImmutablePrivate = "private, max-age=31536000, immutable";

unsigned status_of(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::INVALID_ARGUMENT:
      return 400;
    case grpc::StatusCode::UNAUTHENTICATED:
      return 401;
    case grpc::StatusCode::NOT_FOUND:
    case grpc::StatusCode::OUT_OF_RANGE:
      return 404;
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
      return 503;
    default:
      return 500;
  }
}

HttpMetrics::Route metrics_route(RouteKind kind) {
  switch (kind) {
    case RouteKind::register_texture:
      return HttpMetrics::Route::register_texture;
    case RouteKind::texture:
      return HttpMetrics::Route::texture;
    case RouteKind::brick:
      return HttpMetrics::Route::brick;
    case RouteKind::preflight:
      return HttpMetrics::Route::preflight;
    case RouteKind::refused:
      break;
  }
  return HttpMetrics::Route::other;
}

std::string hex64(uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

// A strong validator: a hash of the exact bytes sent, so two replicas that encode a brick
// differently (another zstd level) never share an ETag.
std::string etag_of(std::string_view payload) {
  return "\"" + hex64(XXH64(payload.data(), payload.size(), 0)) + "\"";
}

// Whether a list of entity tags or "*" (If-Match, If-None-Match) names `etag`: compared
// weakly for If-None-Match, strongly for If-Match, where a weak tag matches nothing (RFC 9110
// 8.8.3.2).
bool tag_list_names(std::string_view header, const std::string& etag, bool weak) {
  while (!header.empty()) {
    const std::size_t comma = header.find(',');
    std::string_view tag = header.substr(0, comma);
    header.remove_prefix(comma == std::string_view::npos ? header.size() : comma + 1);
    tag = without_ows(tag);
    if (tag.starts_with("W/")) {
      if (!weak) continue;
      tag.remove_prefix(2);
    }
    if (tag == "*" || tag == etag) return true;
  }
  return false;
}

// Every line of a list-valued header as one (RFC 9110 5.3), or nothing when it is absent.
std::optional<std::string> joined_lines(const HttpRequest& request, http::field field) {
  std::optional<std::string> value;
  for (auto [it, end] = request.equal_range(field); it != end; ++it) {
    value = value ? *value + ", " + std::string(it->value()) : std::string(it->value());
  }
  return value;
}

// IMF-fixdate (RFC 9110 5.6.7), written without the C locale's names.
std::string http_date(std::time_t now) {
  static constexpr const char* kDays[] = {"Sun", "Mon", "Tue", "Wed", "Thu", "Fri", "Sat"};
  static constexpr const char* kMonths[] = {"Jan", "Feb", "Mar", "Apr", "May", "Jun",
                                            "Jul", "Aug", "Sep", "Oct", "Nov", "Dec"};
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::snprintf(text, sizeof text, "%s, %02d %s %04d %02d:%02d:%02d GMT", kDays[utc.tm_wday],
                utc.tm_mday, kMonths[utc.tm_mon], utc.tm_year + 1900, utc.tm_hour, utc.tm_min,
                utc.tm_sec);
  return text;
}

std::string describe(const Route& route) {
  return "brick (" + std::to_string(route.x) + ", " + std::to_string(route.y) + ", " +
         std::to_string(route.z) + ") level " + std::to_string(route.level) + " of texture " +
         texture_id_hex(route.texture_id);
}

void add_cors(HttpResponse& response) {
  response.set(http::field::access_control_allow_origin, "*");
  response.set(http::field::access_control_expose_headers,
               "ETag, X-Soltex-Codec, X-Soltex-Checksum, X-Cache-Status, Retry-After");
}

}  // namespace

struct HttpRequestHandler::Call {
  unsigned version = 11;
  bool keep_alive = true;
  bool head = false;
  RouteKind kind = RouteKind::refused;
  std::optional<std::string> if_match;
  std::string if_none_match;
  std::string client;
  std::unique_ptr<StreamLease> lease;
  Respond respond;
};

HttpRequestHandler::HttpRequestHandler(Context context)
    : context_(context),
      queue_(std::make_shared<HttpBrickQueue>(context.scheduler, context.producer)) {}

HttpResponse HttpRequestHandler::error(unsigned version, unsigned status,
                                       const std::string& message) const {
  HttpResponse response{static_cast<http::status>(status), version};
  response.set(http::field::content_type, "text/plain; charset=utf-8");
  response.set(http::field::cache_control, "no-store");
  response.set(http::field::date, http_date(std::time(nullptr)));
  // A client over its limits, or a server busy: when to ask again (RFC 9110, 10.2.3).
  if (status == 429 || status == 503) response.set(http::field::retry_after, "1");
  add_cors(response);
  response.body() = message + "\n";
  response.prepare_payload();
  return response;
}

void HttpRequestHandler::finish(Call& call, HttpResponse response) {
  response.version(call.version);
  response.keep_alive(call.keep_alive);
  response.set(http::field::date, http_date(std::time(nullptr)));
  add_cors(response);
  if (response.result() != http::status::not_modified &&
      response.result() != http::status::no_content) {
    response.prepare_payload();
  }
  if (call.head) without_content(response);
  context_.metrics.http.count(metrics_route(call.kind), response.result_int());
  call.lease.reset();
  call.respond(std::move(response));
}

void HttpRequestHandler::handle(const HttpRequest& request, const std::string& peer_host,
                                Respond respond) {
  auto call = std::make_shared<Call>();
  call->version = request.version();
  call->keep_alive = request.keep_alive();
  call->respond = std::move(respond);
  const Route route = route_request(
      std::string_view(request.method_string().data(), request.method_string().size()),
      std::string_view(request.target().data(), request.target().size()));
  call->kind = route.kind;
  call->head = route.head;
  try {
    if (route.kind == RouteKind::refused) {
      HttpResponse response = error(call->version, route.status, route.message);
      if (!route.allow.empty()) response.set(http::field::allow, route.allow);
      return finish(*call, std::move(response));
    }
    if (route.kind == RouteKind::preflight) {
      HttpResponse response{http::status::no_content, call->version};
      response.set(http::field::access_control_allow_methods, route.allow);
      response.set(http::field::access_control_allow_headers,
                   "Authorization, Content-Type, If-Match, If-None-Match");
      response.set(http::field::access_control_max_age, "86400");
      return finish(*call, std::move(response));
    }
    std::vector<std::string_view> forwarded;
    for (auto [it, end] = request.equal_range("x-forwarded-for"); it != end; ++it) {
      forwarded.emplace_back(it->value().data(), it->value().size());
    }
    call->client = context_.access.address_of(peer_host, forwarded);
    const auto authorization = request.find(http::field::authorization);
    const std::string_view token =
        authorization == request.end()
            ? std::string_view{}
            : std::string_view(authorization->value().data(), authorization->value().size());
    const grpc::Status identified = context_.access.check_token(
        authorization == request.end() ? nullptr : &token, call->client);
    if (!identified.ok()) {
      log_refusal(call->client, identified.error_message());
      HttpResponse response = error(call->version, 401, identified.error_message());
      response.set(http::field::www_authenticate, "Bearer");
      return finish(*call, std::move(response));
    }
    grpc::Status refusal;
    call->lease = context_.access.open_stream(call->client, refusal);
    if (!call->lease) throw HttpError{429, refusal.error_message()};
    call->if_match = joined_lines(request, http::field::if_match);
    call->if_none_match = joined_lines(request, http::field::if_none_match).value_or("");
    switch (route.kind) {
      case RouteKind::register_texture:
        context_.metrics.register_requests.fetch_add(1, std::memory_order_relaxed);
        return answer_registration(*call, request.body());
      case RouteKind::texture:
        return answer_texture(route, *call);
      default:
        return handle_brick(route, call);
    }
  } catch (const HttpError& e) {
    if (e.status == 429) log_refusal(call->client, e.message);
    finish(*call, error(call->version, e.status, e.message));
  } catch (const RegistrationError& e) {
    finish(*call, error(call->version, status_of(e.code()), e.what()));
  }
}

void HttpRequestHandler::log_refusal(const std::string& client, const std::string& why) const {
  context_.refusals.refused(client, "HTTP request from " + client + " refused: " + why);
}

void HttpRequestHandler::answer_registration(Call& call, const std::string& body) {
  const v1::RegisterTextureRequest request = registration_from_json(body);
  // The handle's brick URLs must work on any replica, which reads ?spec= up to its bound:
  // a registration whose spec would be longer is refused before it is registered.
  const auto fits_a_url = [](const RegisteredTexture& texture) {
    if (const std::size_t spec = registration_parameter(texture).size();
        spec > kMaxSpecParameterBytes) {
      throw HttpError{413, "the registration is " + std::to_string(spec) +
                               " bytes as its brick URLs' ?spec=; at most " +
                               std::to_string(kMaxSpecParameterBytes) +
                               " fit in a URL: use fewer graph nodes, or register it over gRPC"};
    }
  };
  const TexturePin pin = register_texture(context_.registry, request, call.client, fits_a_url);
  const nlohmann::json handle = handle_json(*pin.texture());
  HttpResponse response{http::status::ok, call.version};
  response.set(http::field::content_type, "application/json");
  response.set(http::field::cache_control, "no-store");
  response.body() = handle.dump() + "\n";
  finish(call, std::move(response));
}

TexturePin HttpRequestHandler::find_or_register(const Route& route, Call& call) {
  TexturePin pin = context_.registry.pin(route.texture_id);
  if (pin) return pin;
  const std::string id = texture_id_hex(route.texture_id);
  if (route.spec.empty()) {
    throw HttpError{404, "texture " + id +
                             " is not registered on this server (POST /v1/textures first, or add "
                             "the ?spec= its handle names; an unused texture may have been "
                             "evicted)"};
  }
  const std::optional<std::string> text = base64url_decode(route.spec);
  if (!text) throw HttpError{400, "spec is not base64url text without padding"};
  context_.metrics.register_requests.fetch_add(1, std::memory_order_relaxed);
  v1::RegisterTextureRequest registration;
  try {
    registration = registration_from_json(*text);
  } catch (const RegistrationError& e) {
    throw HttpError{status_of(e.code()), std::string("spec, decoded: ") + e.what()};
  }
  // Checked before registering: a spec for another texture must not take a registry place.
  if (const uint64_t named = registration_id(registration); named != route.texture_id) {
    throw HttpError{400, "spec registers texture " + texture_id_hex(named) + ", not the texture " +
                             id + " the path names"};
  }
  return register_texture(context_.registry, registration, call.client);
}

void HttpRequestHandler::answer_texture(const Route& route, Call& call) {
  const TexturePin pin = find_or_register(route, call);
  // The texture's JSON carries no ETag: only "*" can match it.
  if (call.if_match && !tag_list_names(*call.if_match, "*", false)) {
    throw HttpError{412,
                    "If-Match names an entity tag; a texture's JSON has none (only * "
                    "matches it)"};
  }
  // It exists, so "*" matches it (RFC 9110 13.1.2): the client's copy is current.
  const bool fresh = tag_list_names(call.if_none_match, "*", true);
  HttpResponse response{fresh ? http::status::not_modified : http::status::ok, call.version};
  response.set(http::field::cache_control,
               context_.access.token_required() ? kImmutablePrivate : kImmutable);
  if (fresh) return finish(call, std::move(response));
  nlohmann::json body = registration_to_json(*pin.texture());
  body["id"] = texture_id_hex(route.texture_id);
  response.set(http::field::content_type, "application/json");
  response.body() = body.dump() + "\n";
  finish(call, std::move(response));
}

void HttpRequestHandler::handle_brick(const Route& route, std::shared_ptr<Call> call) {
  TexturePin pin = find_or_register(route, *call);
  const BrickLayout& layout = pin.texture()->layout;
  if (route.level > static_cast<uint32_t>(layout.coarsest_level())) {
    throw HttpError{404, describe(route) + ": level " + std::to_string(route.level) +
                             " is outside [0, " + std::to_string(layout.coarsest_level()) + "]"};
  }
  const int level = static_cast<int>(route.level);
  const glm::ivec3 brick{static_cast<int>(route.x), static_cast<int>(route.y),
                         static_cast<int>(route.z)};
  if (!layout.contains(level, brick)) {
    throw HttpError{404, describe(route) + ": brick coordinates must be in [0, " +
                             std::to_string(layout.bricks_per_axis(level) - 1) + "] at level " +
                             std::to_string(level)};
  }
  ClientUsage& usage = call->lease->usage();
  if (usage.queued.load(std::memory_order_relaxed) >=
      static_cast<int64_t>(context_.access.max_queued_per_client())) {
    throw HttpError{429, describe(route) + ": client " + usage.client + " has " +
                             std::to_string(context_.access.max_queued_per_client()) +
                             " bricks queued over its streams (max_queued_per_client)"};
  }
  usage.queued.fetch_add(1, std::memory_order_relaxed);
  WorkItem item;
  item.key = {route.texture_id, level, brick};
  item.codec = route.codec;
  item.texture = pin.texture();
  item.enqueued = std::chrono::steady_clock::now();
  // The pin travels with the work: the texture stays registered until its brick is made.
  auto held = std::make_shared<TexturePin>(std::move(pin));
  queue_->submit(std::move(item), [this, call, held, route](const EncodedBrickPtr& brick) {
    call->lease->usage().queued.fetch_sub(1, std::memory_order_relaxed);
    if (!brick) {
      finish(*call, error(call->version, 500,
                          "evaluating " + describe(route) + " failed (see the server log)"));
      return;
    }
    const std::string etag = etag_of(brick->payload());
    if (call->if_match && !tag_list_names(*call->if_match, etag, false)) {
      HttpResponse failed =
          error(call->version, 412, "If-Match does not name this brick's entity tag " + etag);
      failed.set(http::field::etag, etag);
      return finish(*call, std::move(failed));
    }
    const bool fresh =
        !call->if_none_match.empty() && tag_list_names(call->if_none_match, etag, true);
    HttpResponse response{fresh ? http::status::not_modified : http::status::ok, call->version};
    response.set(http::field::etag, etag);
    response.set(http::field::cache_control,
                 context_.access.token_required() ? kImmutablePrivate : kImmutable);
    if (!fresh) {
      response.set(http::field::content_type, "application/vnd.soltex.brick");
      response.set("X-Soltex-Codec", codec_name(brick->codec));
      response.set("X-Soltex-Checksum", hex64(brick->checksum));
      response.body() = std::string(brick->payload());
      // Corrupted on the way out, as a stream's copy is: the ETag and the checksum header
      // still name the brick, which the client's check then refuses.
      if (!call->head && context_.faults != nullptr)
        context_.faults->corrupt_if_due(response.body());
      if (!call->head) {
        context_.metrics.http.bricks_served.fetch_add(1, std::memory_order_relaxed);
        context_.metrics.http.brick_bytes.fetch_add(brick->payload().size(),
                                                    std::memory_order_relaxed);
      }
    }
    finish(*call, std::move(response));
  });
}

}  // namespace soltex::server
