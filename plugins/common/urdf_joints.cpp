#include "urdf_joints.hpp"

#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace ballast::plugin {

std::map<std::string, int> jointFileOrder(const std::string& xml) {
  TiXmlDocument doc;
  doc.Parse(xml.c_str());
  std::map<std::string, int> order;
  if (const TiXmlElement* robot = doc.RootElement()) {
    int n = 0;
    for (const TiXmlElement* e = robot->FirstChildElement("joint"); e;
         e = e->NextSiblingElement("joint"))
      if (const char* name = e->Attribute("name")) order[name] = n++;
  }
  return order;
}

std::vector<UrdfJoint> urdfJoints(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot read the URDF");
  std::stringstream text;
  text << in.rdbuf();
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(text.str());
  if (!model) throw std::runtime_error(path + ": urdfdom could not parse the URDF");
  const std::map<std::string, int> order = jointFileOrder(text.str());
  std::vector<UrdfJoint> joints;
  for (const auto& [name, joint] : model->joints_) {
    UrdfJoint j;
    j.name = name;
    j.movable = joint->type == urdf::Joint::REVOLUTE || joint->type == urdf::Joint::CONTINUOUS ||
                joint->type == urdf::Joint::PRISMATIC;
    if (joint->limits) {
      j.effort = joint->limits->effort;
      j.velocity = joint->limits->velocity;
    }
    joints.push_back(j);
  }
  std::sort(joints.begin(), joints.end(), [&](const UrdfJoint& a, const UrdfJoint& b) {
    const auto ia = order.find(a.name), ib = order.find(b.name);
    return (ia == order.end() ? 1 << 30 : ia->second) < (ib == order.end() ? 1 << 30 : ib->second);
  });
  return joints;
}

}  // namespace ballast::plugin
