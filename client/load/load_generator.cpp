#include "load_generator.h"

#include <grpcpp/grpcpp.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "load_recorder.h"
#include "load_stream.h"
#include "load_texture.h"
#include "open_loop_schedule.h"
#include "request_budget.h"
#include "request_mix.h"

namespace soltex::load {
namespace {

constexpr auto kSetupTimeout = std::chrono::seconds(10);
constexpr auto kProgressInterval = std::chrono::seconds(1);
// After a cancel, gRPC ends a call promptly; this only guards against a hang.
constexpr auto kCancelGrace = std::chrono::seconds(10);
constexpr auto kStopCheck = std::chrono::milliseconds(10);

Clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

std::shared_ptr<grpc::Channel> connect(const std::string& target,
                                       const net::ChannelSecurity& security, int index) {
  grpc::ChannelArguments args;
  // A distinct argument gives every channel its own subchannel, hence its own TCP connection;
  // equal arguments would share one.
  args.SetInt("soltex.load.channel", index);
  args.SetMaxReceiveMessageSize(64 << 20);
  std::shared_ptr<grpc::Channel> channel;
  try {
    channel = net::open_channel(target, security, args);
  } catch (const std::runtime_error& e) {
    throw LoadSetupError(e.what());
  }
  if (!channel->WaitForConnected(std::chrono::system_clock::now() + kSetupTimeout)) {
    throw LoadSetupError("cannot connect to " + target + " within 10 s (connection " +
                         std::to_string(index) + ")");
  }
  return channel;
}

template <typename Call>
void call_with_deadline(const char* what, const net::ChannelSecurity& security, Call call) {
  grpc::ClientContext context;
  net::authorize(security, context);
  context.set_deadline(std::chrono::system_clock::now() + kSetupTimeout);
  const grpc::Status status = call(context);
  if (!status.ok()) {
    throw LoadSetupError(std::string(what) + " failed: " + status_code_name(status.error_code()) +
                         ": " + status.error_message());
  }
}

// Wakes the coordinator whenever something it waits for may have happened.
struct Signal {
  std::mutex mutex;
  std::condition_variable changed;
  int streams_done = 0;
  bool scheduler_done = false;
};

// The connections and what the server said before the load starts.
struct ServerSetup {
  std::vector<std::unique_ptr<v1::BrickService::Stub>> stubs;  // one per connection
  std::vector<std::unique_ptr<BrickStreamStub>> stream_stubs;  // the same connections
  v1::ServerInfo info;
  v1::RegisterTextureRequest registration;
  v1::TextureHandle handle;
  TextureShape shape;
};

ServerSetup set_up_server(const LoadOptions& options) {
  ServerSetup setup;
  setup.registration = texture_registration(options);
  for (int c = 0; c < options.connections; ++c) {
    const std::shared_ptr<grpc::Channel> channel = connect(options.target, options.security, c);
    setup.stubs.push_back(v1::BrickService::NewStub(channel));
    setup.stream_stubs.push_back(std::make_unique<BrickStreamStub>(channel));
  }
  call_with_deadline("GetServerInfo", options.security, [&](grpc::ClientContext& context) {
    return setup.stubs[0]->GetServerInfo(&context, {}, &setup.info);
  });
  call_with_deadline("RegisterTexture", options.security, [&](grpc::ClientContext& context) {
    return setup.stubs[0]->RegisterTexture(&context, setup.registration, &setup.handle);
  });
  setup.shape = {setup.handle.id(), static_cast<int>(setup.handle.levels()),
                 static_cast<int>(setup.handle.brick_size())};
  if (setup.shape.level_count < 1 || setup.shape.level_count > 16) {
    throw LoadSetupError("the server answered RegisterTexture with " +
                         std::to_string(setup.handle.levels()) + " levels; expected 1..16");
  }
  return setup;
}

}  // namespace

LoadResult run_load(LoadOptions options, const ProgressCallback& progress) {
  resolve(options);
  std::vector<RecordedRequest> replay;
  if (options.mix == MixKind::replay) {
    try {
      replay = read_request_log_file(options.replay_file);
    } catch (const RequestLogError& e) {
      throw LoadSetupError(e.what());
    }
    if (replay.empty()) throw LoadSetupError(options.replay_file + ": no requests to replay");
  }
  std::optional<OpenLoopSchedule> schedule;
  try {
    if (options.rate) schedule = OpenLoopSchedule::fixed_rate(*options.rate);
    if (options.replay_speed > 0.0) {
      schedule = OpenLoopSchedule::recorded(replay, options.replay_speed);
    }
  } catch (const std::invalid_argument& e) {
    throw LoadSetupError(options.replay_file + ": " + e.what());
  }

  const ServerSetup server = set_up_server(options);
  const TextureShape& shape = server.shape;

  MixSettings mix;
  mix.kind = options.mix;
  mix.hot_set = options.hot_set;
  mix.replay = replay;
  mix.invalid_fraction = options.invalid_fraction;
  mix.seed = options.seed;
  std::vector<std::unique_ptr<RequestMix>> mixes = make_request_mixes(mix, shape, options.streams);

  LoadStream::Settings settings;
  settings.in_flight = options.open_loop() ? 0 : options.in_flight;
  // 0: a server that states no limit; the server's own default then.
  const uint32_t max_keys = server.info.limits().max_keys_per_request();
  settings.max_keys_per_request = max_keys > 0 ? max_keys : 1024;
  settings.max_backlog = options.max_backlog_per_stream;
  settings.codec = codec_to_proto(options.codec);
  settings.verify = options.verify;
  settings.security = &options.security;
  // Every stream carries its texture, so a balancer may send it to any replica.
  settings.texture = server.registration;

  // ---- Run ---------------------------------------------------------------------------------
  Signal signal;
  const Clock::time_point start = Clock::now();
  const Clock::time_point measure_from = start + seconds(options.warmup_seconds);
  const Clock::time_point stop_at =
      measure_from + seconds(options.duration_seconds.value_or(LoadBounds::kMaxSeconds));
  LoadRecorder recorder(measure_from);
  RequestBudget budget(options.count);

  std::vector<std::unique_ptr<LoadStream>> streams;
  for (int s = 0; s < options.streams; ++s) {
    streams.push_back(std::make_unique<LoadStream>(
        *server.stream_stubs[static_cast<std::size_t>(s % options.connections)], settings,
        std::move(mixes[static_cast<std::size_t>(s)]), recorder, budget, [&signal] {
          std::lock_guard lock(signal.mutex);
          ++signal.streams_done;
          signal.changed.notify_all();
        }));
  }
  for (auto& stream : streams) stream->start();

  std::thread scheduler;
  std::atomic<bool> stop_scheduler{false};
  bool schedule_ran_out = false;  // written by the scheduler, read after joining it
  Clock::duration max_send_lag{0};
  if (schedule) {
    // Request i goes to stream i mod S at its intended time; when the sender falls behind it
    // sends at once, and the latency still counts from the intended time.
    scheduler = std::thread([&] {
      for (uint64_t i = 0;; ++i) {
        const Clock::time_point intended = start + seconds(schedule->seconds(i));
        if (intended >= stop_at) {
          schedule_ran_out = true;
          break;
        }
        // A plain sleep, not a condition variable: at tens of thousands of requests per
        // second the futex traffic of a timed wait per request cost more than the sends.
        // Sliced, so that a stop is seen within kStopCheck.
        for (Clock::time_point now = Clock::now();
             now < intended && !stop_scheduler.load(std::memory_order_relaxed);
             now = Clock::now()) {
          std::this_thread::sleep_until(std::min(intended, now + kStopCheck));
        }
        if (stop_scheduler.load(std::memory_order_relaxed)) break;
        max_send_lag = std::max(max_send_lag, Clock::now() - intended);
        LoadStream& stream = *streams[i % streams.size()];
        if (!stream.issue(intended) && budget.exhausted()) break;
      }
      std::lock_guard lock(signal.mutex);
      signal.scheduler_done = true;
      signal.changed.notify_all();
    });
  }

  Clock::time_point next_tick = start + kProgressInterval;
  uint64_t last_bricks = 0;
  Clock::time_point last_tick = start;
  bool draining = false;
  const auto report_progress = [&](Clock::time_point now) {
    if (!progress) return;
    const LoadRecorder::Progress p = recorder.progress();
    ProgressLine line;
    line.elapsed_seconds = std::chrono::duration<double>(now - start).count();
    line.warmup = now < measure_from;
    line.draining = draining;
    line.bricks = p.bricks;
    line.errors = p.errors;
    const double interval = std::chrono::duration<double>(now - last_tick).count();
    line.bricks_per_second =
        interval > 0.0 ? static_cast<double>(p.bricks - last_bricks) / interval : 0.0;
    last_bricks = p.bricks;
    last_tick = now;
    progress(line);
  };
  // Waits until `until`, printing progress on the way; true when `finished` came true.
  const auto wait = [&](Clock::time_point until, const auto& finished) {
    for (;;) {
      {
        std::unique_lock lock(signal.mutex);
        signal.changed.wait_until(lock, std::min(until, next_tick), [&] { return finished(); });
        if (finished()) return true;
      }
      const Clock::time_point now = Clock::now();
      if (now >= next_tick) {
        report_progress(now);
        next_tick += kProgressInterval;
      }
      if (now >= until) return false;
    }
  };
  const auto all_done = [&] { return signal.streams_done == static_cast<int>(streams.size()); };

  // Load until the stop time, the count is spent (closed-loop streams close themselves; the
  // open-loop scheduler ends) or every stream has ended.
  wait(stop_at, [&] { return all_done() || signal.scheduler_done; });
  stop_scheduler = true;
  if (scheduler.joinable()) scheduler.join();
  // The measured window: a count run ends with its last answer; a schedule that ran out
  // offered load until the stop time; otherwise (the stop time, or every stream ended) now.
  Clock::time_point window_end = measure_from;
  if (!budget.exhausted()) {
    window_end = schedule_ran_out ? stop_at : std::min(stop_at, Clock::now());
  }

  // Drain: what was issued is still sent and answered, up to the drain timeout.
  draining = true;
  for (auto& stream : streams) stream->close();
  if (!wait(Clock::now() + seconds(options.drain_timeout_seconds), all_done)) {
    for (auto& stream : streams) {
      if (!stream->done()) stream->cancel();
    }
    if (!wait(Clock::now() + kCancelGrace, all_done)) {
      // A call that does not end after a cancel would be a gRPC fault; its stream object
      // must outlive gRPC's reference to it, so it is left allocated rather than freed early.
      for (auto& stream : streams) {
        if (!stream->done()) (void)stream.release();
      }
    }
  }
  const Clock::time_point end = Clock::now();

  LoadResult result;
  result.options = options;
  result.texture_id = server.handle.id();
  result.texture_levels = shape.level_count;
  result.server_workers = static_cast<int>(server.info.worker_threads());
  result.elapsed_seconds = std::chrono::duration<double>(std::max(end, window_end) - start).count();
  result.max_send_lag_seconds = std::chrono::duration<double>(max_send_lag).count();
  recorder.fill(result, window_end);
  return result;
}

}  // namespace soltex::load
