"""A Gazebo world file with spherical coordinates, as Husarion's simulation ships one (`sim world`)."""

from __future__ import annotations

WORLD = """<?xml version="1.0" ?>
<sdf version="1.6">
  <world name="husarion_world">
    <!-- the origin of the NavSat sensors -->
    <spherical_coordinates>
      <surface_model>EARTH_WGS84</surface_model>
      <world_frame_orientation>ENU</world_frame_orientation>
      <latitude_deg>53.1978</latitude_deg>
      <longitude_deg>18.3732</longitude_deg>
      <elevation>0</elevation>
    </spherical_coordinates>
    <gravity>0 0 -9.8</gravity>
  </world>
</sdf>
"""
