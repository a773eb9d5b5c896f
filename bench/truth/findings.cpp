#include "bench/truth/findings.h"

#include <cmath>

namespace omnishadow::bench {

std::string_view to_string(Status s) {
  switch (s) {
    case Status::ok:
      return "ok";
    case Status::failed_quality:
      return "failed_quality";
    case Status::failed_check:
      return "failed_check";
    case Status::interrupted:
      return "interrupted";
    case Status::resource_error:
      return "resource_error";
    case Status::failed:
      return "failed";
    case Status::crashed:
      return "crashed";
    case Status::unsupported:
      return "unsupported";
  }
  return "?";
}

std::optional<Status> status_named(std::string_view name) {
  for (int i = int(Status::ok); i <= int(Status::unsupported); ++i)
    if (name == to_string(Status(i))) return Status(i);
  return std::nullopt;
}

bool fails_run(Status s) {
  return s == Status::failed_quality || s == Status::failed_check || s == Status::resource_error ||
         s == Status::failed || s == Status::crashed;
}

void CaseFindings::add(Finding finding) {
  if (static_cast<int>(finding.status) > static_cast<int>(status)) status = finding.status;
  reason += (reason.empty() ? "" : "; ") + finding.message;
  findings.push_back(std::move(finding));
}

int checked_light_stride(int light_count) {
  return light_count <= kCheckedLights ? 1 : (light_count + kCheckedLights - 1) / kCheckedLights;
}

std::vector<int> checked_lights(int light_count) {
  std::vector<int> lights;
  for (int k = 0; k < light_count; k += checked_light_stride(light_count)) lights.push_back(k);
  return lights;
}

void merge_light_findings(CaseFindings& into, int light, CaseFindings&& from) {
  const std::string prefix = "light " + std::to_string(light) + ": ";
  for (Finding& f : from.findings) {
    f.message = prefix + f.message;
    into.add(std::move(f));
  }
  for (CheckResult& c : from.checks) {
    c.name += "@l" + std::to_string(light);
    into.checks.push_back(std::move(c));
  }
  for (auto& [role, path] : from.images) into.images.emplace(role + "@l" + std::to_string(light), path);
  into.per_light.push_back({light, from.accuracy, from.cube_texels, from.lookups});
}

std::optional<Accuracy> pooled_accuracy(const std::vector<LightReport>& lights) {
  Accuracy a;
  double pixels = 0, sphere_pixels = 0, mse_point = 0, mse_sphere = 0;
  bool point_errs = false, sphere_errs = false;
  // A PSNR back to its mean squared error (accuracy.cpp: 10 log10(1 / mse), peak 1; -1 for none).
  auto mse = [](double db) { return db < 0 ? 0.0 : std::pow(10.0, -db / 10.0); };
  for (const LightReport& l : lights) {
    if (!l.accuracy || l.accuracy->pixels == 0) continue;
    const Accuracy& x = *l.accuracy;
    const double n = double(x.pixels);
    pixels += n;
    a.pixels += x.pixels;
    a.misclassified_percent += x.misclassified_percent * n;
    a.false_shadow_percent += x.false_shadow_percent * n;
    a.missed_shadow_percent += x.missed_shadow_percent * n;
    a.mae_point += x.mae_point * n;
    mse_point += mse(x.psnr_point_db) * n;
    point_errs = point_errs || x.psnr_point_db >= 0;
    a.sphere_stride = x.sphere_stride;
    if (x.mae_sphere >= 0) {
      const double s = double(x.sphere_pixels);
      sphere_pixels += s;
      a.sphere_pixels += x.sphere_pixels;
      a.mae_sphere = std::max(a.mae_sphere, 0.0) + x.mae_sphere * s;
      mse_sphere += mse(x.psnr_sphere_db) * s;
      sphere_errs = sphere_errs || x.psnr_sphere_db >= 0;
    }
  }
  if (pixels == 0) return std::nullopt;
  for (double* v :
       {&a.misclassified_percent, &a.false_shadow_percent, &a.missed_shadow_percent, &a.mae_point})
    *v /= pixels;
  a.psnr_point_db = point_errs ? 10.0 * std::log10(pixels / mse_point) : -1.0;
  if (sphere_pixels > 0) {
    a.mae_sphere /= sphere_pixels;
    a.psnr_sphere_db = sphere_errs ? 10.0 * std::log10(sphere_pixels / mse_sphere) : -1.0;
  }
  return a;
}

}  // namespace omnishadow::bench
