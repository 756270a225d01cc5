// SPDX-License-Identifier: MIT
#include "meshgen/segmentation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace softbench::meshgen {
namespace {

// Labels each 6-connected component of voxels whose value equals `value`; returns per-voxel
// component ids (-1 for other voxels) and the size of each component.
struct Components {
  std::vector<int> id;
  std::vector<int> sizes;
  std::vector<bool> touches_border;
};

Components label_components(const ScalarGrid& labels, float value) {
  const Eigen::Vector3i& n = labels.size;
  Components components;
  components.id.assign(labels.values.size(), -1);
  std::vector<Eigen::Vector3i> stack;
  for (int k = 0; k < n.z(); ++k) {
    for (int j = 0; j < n.y(); ++j) {
      for (int i = 0; i < n.x(); ++i) {
        const std::size_t seed = labels.index(i, j, k);
        if (labels.values[seed] != value || components.id[seed] >= 0) {
          continue;
        }
        const int component = static_cast<int>(components.sizes.size());
        components.sizes.push_back(0);
        components.touches_border.push_back(false);
        components.id[seed] = component;
        stack.assign(1, Eigen::Vector3i(i, j, k));
        while (!stack.empty()) {
          const Eigen::Vector3i voxel = stack.back();
          stack.pop_back();
          ++components.sizes[static_cast<std::size_t>(component)];
          for (int axis = 0; axis < 3; ++axis) {
            for (int step : {-1, 1}) {
              Eigen::Vector3i next = voxel;
              next(axis) += step;
              if (next(axis) < 0 || next(axis) >= n(axis)) {
                components.touches_border[static_cast<std::size_t>(component)] = true;
                continue;
              }
              const std::size_t index = labels.index(next.x(), next.y(), next.z());
              if (labels.values[index] == value && components.id[index] < 0) {
                components.id[index] = component;
                stack.push_back(next);
              }
            }
          }
        }
      }
    }
  }
  return components;
}

}  // namespace

ScalarGrid threshold_segment(const ScalarGrid& intensity, float threshold) {
  ScalarGrid labels = intensity;
  for (float& value : labels.values) {
    value = value > threshold ? 1.0f : 0.0f;
  }
  return labels;
}

int remove_islands(ScalarGrid& labels) {
  const Components components = label_components(labels, 1.0f);
  if (components.sizes.empty()) {
    return 0;
  }
  const int largest =
      static_cast<int>(std::max_element(components.sizes.begin(), components.sizes.end())
                       - components.sizes.begin());
  int removed = 0;
  for (std::size_t v = 0; v < labels.values.size(); ++v) {
    if (components.id[v] >= 0 && components.id[v] != largest) {
      labels.values[v] = 0.0f;
      ++removed;
    }
  }
  return removed;
}

int fill_cavities(ScalarGrid& labels) {
  const Components components = label_components(labels, 0.0f);
  int filled = 0;
  for (std::size_t v = 0; v < labels.values.size(); ++v) {
    const int component = components.id[v];
    if (component >= 0 && !components.touches_border[static_cast<std::size_t>(component)]) {
      labels.values[v] = 1.0f;
      ++filled;
    }
  }
  return filled;
}

ScalarGrid gaussian_blur(const ScalarGrid& grid, double sigma_voxels) {
  const int radius = std::max(1, static_cast<int>(std::ceil(3.0 * sigma_voxels)));
  std::vector<double> kernel(static_cast<std::size_t>(2 * radius + 1));
  double total = 0.0;
  for (int offset = -radius; offset <= radius; ++offset) {
    const double weight = std::exp(-0.5 * offset * offset / (sigma_voxels * sigma_voxels));
    kernel[static_cast<std::size_t>(offset + radius)] = weight;
    total += weight;
  }
  for (double& weight : kernel) {
    weight /= total;
  }

  ScalarGrid source = grid;
  ScalarGrid result = grid;
  for (int axis = 0; axis < 3; ++axis) {
    const int length = grid.size(axis);
    for (int k = 0; k < grid.size.z(); ++k) {
      for (int j = 0; j < grid.size.y(); ++j) {
        for (int i = 0; i < grid.size.x(); ++i) {
          Eigen::Vector3i voxel(i, j, k);
          double sum = 0.0;
          for (int offset = -radius; offset <= radius; ++offset) {
            Eigen::Vector3i sample = voxel;
            sample(axis) = std::clamp(voxel(axis) + offset, 0, length - 1);
            sum += kernel[static_cast<std::size_t>(offset + radius)]
                   * source.at(sample.x(), sample.y(), sample.z());
          }
          result.at(i, j, k) = static_cast<float>(sum);
        }
      }
    }
    std::swap(source, result);
  }
  return source;
}

}  // namespace softbench::meshgen
