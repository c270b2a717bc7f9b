#include "load_generator.h"

#include <grpcpp/grpcpp.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
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

std::vector<RecordedRequest> read_replay(const LoadOptions& options) {
  if (options.mix != MixKind::replay) return {};
  std::vector<RecordedRequest> replay;
  try {
    replay = read_request_log_file(options.replay_file);
  } catch (const RequestLogError& e) {
    throw LoadSetupError(e.what());
  }
  if (replay.empty()) throw LoadSetupError(options.replay_file + ": no requests to replay");
  // The log keeps keys, not the volume they were cut from: say which finest level the keys
  // need rather than let nearly every one be refused as out of range.
  // At level l a volume of 2^L cells has 2^(L - l) / B bricks a side: coordinate c needs
  // L >= l + log2 B + bit_width(c).
  const int log2_brick = std::countr_zero(static_cast<unsigned>(options.brick_size));
  int needed = 0;
  for (const RecordedRequest& r : replay) {
    const auto widest = static_cast<uint32_t>(std::max({r.x, r.y, r.z, 0}));
    needed = std::max(needed, r.level + log2_brick + static_cast<int>(std::bit_width(widest)));
  }
  if (needed > options.finest_level) {
    throw LoadOptionsError(options.replay_file + ": its keys need --finest-level " +
                           std::to_string(needed) + " or more (with --brick-size " +
                           std::to_string(options.brick_size) + "); the volume has 2^" +
                           std::to_string(options.finest_level) +
                           " cells, so they would be refused as out of range");
  }
  return replay;
}

// Open loop: a fixed rate, or the recorded times of a replay; closed loop: none.
std::optional<OpenLoopSchedule> open_loop_schedule(const LoadOptions& options,
                                                   const std::vector<RecordedRequest>& replay) {
  std::optional<OpenLoopSchedule> schedule;
  try {
    if (options.rate) schedule = OpenLoopSchedule::fixed_rate(*options.rate);
    if (options.replay_speed > 0.0) {
      schedule = OpenLoopSchedule::recorded(replay, options.replay_speed);
    }
  } catch (const std::invalid_argument& e) {
    throw LoadSetupError(options.replay_file + ": " + e.what());
  }
  return schedule;
}

LoadStream::Settings stream_settings(const LoadOptions& options, const ServerSetup& server) {
  LoadStream::Settings settings;
  settings.in_flight = options.open_loop() ? 0 : options.in_flight;
  // 0: a server that states no limit; the server's own default then.
  const uint32_t max_keys = server.info.limits().max_keys_per_request();
  settings.max_keys_per_request = max_keys > 0 ? max_keys : 1024;
  if (const uint32_t max_bytes = server.info.limits().max_message_bytes(); max_bytes > 0) {
    settings.max_message_bytes = max_bytes;
  }
  settings.max_backlog = options.max_backlog_per_stream;
  settings.codec = codec_to_proto(options.codec);
  settings.verify = options.verify;
  settings.security = &options.security;
  // Every stream carries its texture, so a balancer may send it to any replica.
  settings.texture = server.registration;
  return settings;
}

// One load run against a set-up server: its streams, the open-loop scheduler if any, the
// progress lines, and the drain at the end.
class LoadRun {
 public:
  LoadRun(const LoadOptions& options, const ProgressCallback& progress)
      : options_(options),
        progress_(progress),
        start_(Clock::now()),
        measure_from_(start_ + seconds(options.warmup_seconds)),
        stop_at_(measure_from_ +
                 seconds(options.duration_seconds.value_or(LoadBounds::kMaxSeconds))),
        recorder_(measure_from_),
        budget_(options.count),
        next_tick_(start_ + kProgressInterval),
        last_tick_(start_) {}

  LoadRun(const LoadRun&) = delete;
  LoadRun& operator=(const LoadRun&) = delete;

  // Normally after run(); after an exception in it, the streams still open are cancelled
  // first, so that no gRPC callback reaches a freed stream.
  ~LoadRun() {
    stop_scheduler_ = true;
    if (scheduler_.joinable()) scheduler_.join();
    if (!drained_) abandon_streams();
  }

  // One stream per mix.
  LoadResult run(const ServerSetup& server, std::vector<std::unique_ptr<RequestMix>> mixes,
                 std::optional<OpenLoopSchedule> schedule);

 private:
  void start_streams(const ServerSetup& server, std::vector<std::unique_ptr<RequestMix>> mixes);
  void run_schedule(const OpenLoopSchedule& schedule);
  Clock::time_point load_until_stop();
  void drain();
  void abandon_streams();
  void report_progress(Clock::time_point now);
  bool all_done() const { return signal_.streams_done == static_cast<int>(streams_.size()); }

  // Waits until `until`, printing progress on the way; true when `finished` came true.
  // `finished` runs with signal_.mutex held, so the caller must not hold it.
  template <typename Finished>
  bool wait(Clock::time_point until, const Finished& finished) {
    for (;;) {
      {
        std::unique_lock lock(signal_.mutex);
        signal_.changed.wait_until(lock, std::min(until, next_tick_), [&] { return finished(); });
        if (finished()) return true;
      }
      const Clock::time_point now = Clock::now();
      if (now >= next_tick_) {
        report_progress(now);
        next_tick_ += kProgressInterval;
      }
      if (now >= until) return false;
    }
  }

  const LoadOptions& options_;
  const ProgressCallback& progress_;
  const Clock::time_point start_, measure_from_, stop_at_;
  Signal signal_;
  LoadRecorder recorder_;
  RequestBudget budget_;
  // After what they refer to (signal_, recorder_, budget_), so destroyed before them.
  std::vector<std::unique_ptr<LoadStream>> streams_;
  std::thread scheduler_;
  std::atomic<bool> stop_scheduler_{false};
  bool schedule_ran_out_ = false;  // written by the scheduler, read after joining it
  Clock::duration max_send_lag_{0};
  Clock::time_point next_tick_, last_tick_;
  uint64_t last_bricks_ = 0;
  bool draining_ = false;
  bool drained_ = false;  // drain() ran to its end: every stream is done or let go
};

LoadResult LoadRun::run(const ServerSetup& server, std::vector<std::unique_ptr<RequestMix>> mixes,
                        std::optional<OpenLoopSchedule> schedule) {
  start_streams(server, std::move(mixes));
  if (schedule) {
    scheduler_ = std::thread([this, s = std::move(*schedule)] { run_schedule(s); });
  }
  const Clock::time_point window_end = load_until_stop();
  drain();
  const Clock::time_point end = Clock::now();

  LoadResult result;
  result.options = options_;
  result.texture_id = server.handle.id();
  result.texture_levels = server.shape.level_count;
  result.server_workers = static_cast<int>(server.info.worker_threads());
  result.elapsed_seconds =
      std::chrono::duration<double>(std::max(end, window_end) - start_).count();
  result.max_send_lag_seconds = std::chrono::duration<double>(max_send_lag_).count();
  recorder_.fill(result, window_end);
  return result;
}

void LoadRun::start_streams(const ServerSetup& server,
                            std::vector<std::unique_ptr<RequestMix>> mixes) {
  const LoadStream::Settings settings = stream_settings(options_, server);
  const auto on_done = [this] {
    std::lock_guard lock(signal_.mutex);
    ++signal_.streams_done;
    signal_.changed.notify_all();
  };
  for (std::size_t i = 0; i < mixes.size(); ++i) {
    BrickStreamStub& stub = *server.stream_stubs[i % server.stream_stubs.size()];
    streams_.push_back(std::make_unique<LoadStream>(stub, settings, std::move(mixes[i]), recorder_,
                                                    budget_, on_done));
    // Started at once, so that every stream in streams_ is one gRPC knows of (what
    // abandon_streams() relies on).
    streams_.back()->start();
  }
}

// Request i goes to stream i mod S at its intended time; when the sender falls behind it
// sends at once, and the latency still counts from the intended time.
void LoadRun::run_schedule(const OpenLoopSchedule& schedule) {
  for (uint64_t i = 0;; ++i) {
    const Clock::time_point intended = start_ + seconds(schedule.seconds(i));
    if (intended >= stop_at_) {
      schedule_ran_out_ = true;
      break;
    }
    // A plain sleep, not a condition variable: at tens of thousands of requests per second
    // the futex traffic of a timed wait per request cost more than the sends. Sliced, so that
    // a stop is seen within kStopCheck.
    for (Clock::time_point now = Clock::now();
         now < intended && !stop_scheduler_.load(std::memory_order_relaxed); now = Clock::now()) {
      std::this_thread::sleep_until(std::min(intended, now + kStopCheck));
    }
    if (stop_scheduler_.load(std::memory_order_relaxed)) break;
    max_send_lag_ = std::max(max_send_lag_, Clock::now() - intended);
    LoadStream& stream = *streams_[i % streams_.size()];
    if (!stream.issue(intended) && budget_.exhausted()) break;
  }
  std::lock_guard lock(signal_.mutex);
  signal_.scheduler_done = true;
  signal_.changed.notify_all();
}

// Loads until the stop time, the count is spent (closed-loop streams close themselves; the
// open-loop scheduler ends) or every stream has ended; returns the end of the measured window.
Clock::time_point LoadRun::load_until_stop() {
  wait(stop_at_, [&] { return all_done() || signal_.scheduler_done; });
  stop_scheduler_ = true;
  if (scheduler_.joinable()) scheduler_.join();
  // A count run ends with its last answer; a schedule that ran out offered load until the
  // stop time; otherwise (the stop time, or every stream ended) now.
  if (budget_.exhausted()) return measure_from_;
  return schedule_ran_out_ ? stop_at_ : std::min(stop_at_, Clock::now());
}

// What was issued is still sent and answered, up to the drain timeout.
void LoadRun::drain() {
  draining_ = true;
  for (auto& stream : streams_) stream->close();
  if (!wait(Clock::now() + seconds(options_.drain_timeout_seconds), [&] { return all_done(); })) {
    abandon_streams();
  }
  drained_ = true;
}

// Cancels the streams still open and waits a grace period for gRPC to end them.
void LoadRun::abandon_streams() {
  for (auto& stream : streams_) {
    if (!stream->done()) stream->cancel();
  }
  {
    std::unique_lock lock(signal_.mutex);
    if (signal_.changed.wait_for(lock, kCancelGrace, [&] { return all_done(); })) return;
  }
  // A call that does not end after a cancel would be a gRPC fault; its stream object must
  // outlive gRPC's reference to it, so it is left allocated rather than freed early.
  for (auto& stream : streams_) {
    if (!stream->done()) (void)stream.release();
  }
}

void LoadRun::report_progress(Clock::time_point now) {
  if (!progress_) return;
  const LoadRecorder::Progress p = recorder_.progress();
  ProgressLine line;
  line.elapsed_seconds = std::chrono::duration<double>(now - start_).count();
  line.warmup = now < measure_from_;
  line.draining = draining_;
  line.bricks = p.bricks;
  line.errors = p.errors;
  const double interval = std::chrono::duration<double>(now - last_tick_).count();
  line.bricks_per_second =
      interval > 0.0 ? static_cast<double>(p.bricks - last_bricks_) / interval : 0.0;
  last_bricks_ = p.bricks;
  last_tick_ = now;
  progress_(line);
}

}  // namespace

LoadResult run_load(LoadOptions options, const ProgressCallback& progress) {
  resolve(options);
  const std::vector<RecordedRequest> replay = read_replay(options);
  std::optional<OpenLoopSchedule> schedule = open_loop_schedule(options, replay);
  const ServerSetup server = set_up_server(options);
  MixSettings mix;
  mix.kind = options.mix;
  mix.hot_set = options.hot_set;
  mix.replay = replay;
  mix.invalid_fraction = options.invalid_fraction;
  mix.seed = options.seed;
  std::vector<std::unique_ptr<RequestMix>> mixes =
      make_request_mixes(mix, server.shape, options.streams);
  LoadRun run(options, progress);
  return run.run(server, std::move(mixes), std::move(schedule));
}

}  // namespace soltex::load
