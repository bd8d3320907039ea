// The observer of one case: sampled histories, the metrics of every step, and the wear the
// driver deposits, recorded as the case's wear metrics and maps.
#include "sweep/case_observer.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace rodend {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

CaseArray case_array(std::string group, std::string name, std::string unit, std::string description,
                     std::vector<std::size_t> dims, std::vector<double> values) {
  // netCDF dimensions: a wear map is latitude x longitude cells, a per-row array is per
  // latitude, the radii are per body (ball, socket), an evolution column per update
  std::vector<std::string> dim_names;
  if (group == "evolution")
    dim_names = {"update"};
  else if (name == "longitude")
    dim_names = {"longitude"};
  else if (name == "radius")
    dim_names = {"body"};
  else if (dims.size() == 2)
    dim_names = {"latitude", "longitude"};
  else
    dim_names = {"latitude"};
  return {std::move(group), std::move(name),   std::move(unit),     std::move(description),
          std::move(dims),  std::move(values), std::move(dim_names)};
}

CaseRecord start_record(const CaseSpec& spec) {
  CaseRecord rec;
  rec.id = spec.id;
  rec.index = spec.index;
  rec.scene = spec.scene;
  rec.coordinates = spec.coordinates;
  rec.started_utc = utc_now();
  rec.metrics.fill(kNaN);
  return rec;
}

CaseObserver::CaseObserver(const Scene& scene, const CaseSpec& spec, History* h)
    : history_(h), metrics_(scene, spec.metrics), sliding_work_(kNaN) {
  if (h) {
    h->signals = spec.signals;
    h->values.assign(spec.signals.size(), {});
    h->samples = 0;
    h->arrays.clear();
    const auto n =
        static_cast<std::size_t>(std::floor(spec.time.end / spec.time.sample_interval + 1e-9) + 1);
    for (std::size_t i = 0; i < spec.signals.size(); ++i)
      h->values[i].reserve(n * static_cast<std::size_t>(signal_spec(spec.signals[i]).width));
  }
  if (const WearModel* w = scene.wear_model()) wear_.emplace(*w);
  if (h)
    for (const SensorSpec& s : active_sensors(spec.sensors, scene))
      sensors_.emplace_back(s, spec.sensors.noise_scale, spec.sensors.seed, spec.design_sample);
}

void CaseObserver::on_step(const SignalFrame& f) {
  metrics_.on_step(f);
  for (SensorChannel& s : sensors_) s.advance(f);
}

void CaseObserver::record_sensors(MetricValues& m, History& h) const {
  metrics_.finish_sensed(sensors_, m);
  for (const SensorChannel& s : sensors_) {
    const SensorSpec& x = s.spec();
    const std::string time = x.name + "_time", unit(signal_spec(s.signal()).unit);
    const std::size_t n = s.times().size();
    std::string what = "sensor " + x.name + ": " + x.signal;
    if (signal_spec(s.signal()).width > 1) what += "[" + std::to_string(x.component) + "]";
    h.arrays.push_back(
        {"sensors", time, "s", "sample times of sensor " + x.name, {n}, s.times(), {time}});
    h.arrays.push_back({"sensors",
                        x.name,
                        unit,
                        what + " as the instrument reports it (noise, " +
                            "bias, quantisation, low-pass, own sampling rate: docs/sensors.md)",
                        {n},
                        s.values(),
                        {time}});
  }
}

std::atomic<bool>& case_interrupt() {
  static std::atomic<bool> flag{false};
  static_assert(std::atomic<bool>::is_always_lock_free);
  return flag;
}

void CaseObserver::on_sample(const SignalFrame& f) {
  if (case_interrupt().load(std::memory_order_relaxed)) throw CaseInterrupted{};
  if (wear_) sliding_work_ = f.get(SignalId::sliding_work);
  if (!history_) return;
  if (!sensors_started_) {  // the frame at t = 0 starts them; the later samples are not theirs
    for (SensorChannel& s : sensors_) s.start(f);
    sensors_started_ = true;
  }
  for (std::size_t i = 0; i < history_->signals.size(); ++i) {
    const SignalId id = history_->signals[i];
    const double* v = f.data(id);
    std::vector<double>& column = history_->values[i];
    const int width = signal_spec(id).width;
    if (width == 1)
      column.push_back(*v);  // most signals: no memmove call per value
    else
      column.insert(column.end(), v, v + width);
  }
  ++history_->samples;
}

void CaseObserver::record_wear(MetricValues& m, History& h) const {
  if (!wear_) return;
  metric(m, MetricId::sliding_work) = sliding_work_;
  record_wear_maps(wear_->ball(), wear_->socket(), m, h);
}

void record_wear_maps(const WearMap& ball, const WearMap& socket, MetricValues& m, History& h) {
  metric(m, MetricId::worn_volume_ball) = ball.volume();
  metric(m, MetricId::worn_volume_socket) = socket.volume();
  const WearMap::Extreme b = ball.max_depth(), s = socket.max_depth();
  metric(m, MetricId::max_wear_depth_ball) = b.depth;
  metric(m, MetricId::max_wear_depth_ball_longitude) = b.longitude;
  metric(m, MetricId::max_wear_depth_ball_latitude) = b.latitude;
  metric(m, MetricId::max_wear_depth_socket) = s.depth;
  metric(m, MetricId::max_wear_depth_socket_longitude) = s.longitude;
  metric(m, MetricId::max_wear_depth_socket_latitude) = s.latitude;

  const auto nlon = static_cast<std::size_t>(ball.n_longitude());
  const auto nlat = static_cast<std::size_t>(ball.n_latitude());
  std::vector<double> lon(nlon), lat(nlat), area_b(nlat), area_s(nlat);
  for (std::size_t i = 0; i < nlon; ++i) lon[i] = ball.longitude(static_cast<int>(i));
  for (std::size_t j = 0; j < nlat; ++j) {
    lat[j] = ball.latitude(static_cast<int>(j));
    area_b[j] = ball.cell_area(static_cast<int>(j));
    area_s[j] = socket.cell_area(static_cast<int>(j));
  }
  const std::string g = "wear";
  h.arrays.push_back(case_array(g, "longitude", "rad",
                                "cell-centre longitude about the body's z axis, from +x", {nlon},
                                lon));
  h.arrays.push_back(case_array(g, "latitude", "rad",
                                "cell-centre latitude from the body's xy-plane", {nlat}, lat));
  h.arrays.push_back(case_array(g, "ball_depth", "m",
                                "worn depth of the ball, latitude x longitude cells, ball frame",
                                {nlat, nlon}, ball.depths()));
  h.arrays.push_back(case_array(
      g, "socket_depth", "m", "worn depth of the socket, latitude x longitude cells, socket frame",
      {nlat, nlon}, socket.depths()));
  h.arrays.push_back(case_array(g, "ball_cell_area", "m^2",
                                "area of a ball cell in each latitude row (depth x area = volume)",
                                {nlat}, area_b));
  h.arrays.push_back(case_array(g, "socket_cell_area", "m^2",
                                "area of a socket cell in each latitude row", {nlat}, area_s));
  h.arrays.push_back(case_array(g, "radius", "m", "radii of the ball and socket maps", {2},
                                {ball.radius(), socket.radius()}));
}

}  // namespace rodend
