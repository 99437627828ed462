// A toolinc point set as a PCL cloud, for the benchmarks that compare with PCL.
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "toolinc/core/point_cloud.hpp"

inline pcl::PointCloud<pcl::PointXYZ>::Ptr to_pcl(const toolinc::Points& points) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (const auto& p : points)
    cloud->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())));
  return cloud;
}
