#include "vk/context.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>

namespace wetdem::vk {

void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw std::runtime_error(fmt::format("Vulkan call failed ({}): {}", int(r), what));
}

namespace {

const char* type_name(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "CPU";
    default:
      return "other";
  }
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

int type_rank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 3;
    default:
      return 4;
  }
}

bool has_layer(const char* name) {
  uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> props(n);
  vkEnumerateInstanceLayerProperties(&n, props.data());
  for (auto& p : props)
    if (std::strcmp(p.layerName, name) == 0) return true;
  return false;
}

VkInstance make_instance(bool validation) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "wetdem";
  app.apiVersion = VK_API_VERSION_1_2;
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  const char* layer = "VK_LAYER_KHRONOS_validation";
  const char* ext = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
  if (validation) {
    ci.enabledLayerCount = 1;
    ci.ppEnabledLayerNames = &layer;
    ci.enabledExtensionCount = 1;
    ci.ppEnabledExtensionNames = &ext;
  }
  VkInstance inst;
  WETDEM_VK(vkCreateInstance(&ci, nullptr, &inst));
  return inst;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance inst) {
  uint32_t n = 0;
  WETDEM_VK(vkEnumeratePhysicalDevices(inst, &n, nullptr));
  std::vector<VkPhysicalDevice> devs(n);
  WETDEM_VK(vkEnumeratePhysicalDevices(inst, &n, devs.data()));
  return devs;
}

}  // namespace

std::string DeviceInfo::describe() const {
  return fmt::format("{} (driver {} {}, {})", name, driver_name, driver_info, type_name(type));
}

std::vector<std::string> Context::list_devices() {
  VkInstance inst = make_instance(false);
  std::vector<std::string> out;
  auto devs = physical_devices(inst);
  for (size_t i = 0; i < devs.size(); ++i) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(devs[i], &p);
    out.push_back(fmt::format("{}: {} ({})", i, p.deviceName, type_name(p.deviceType)));
  }
  vkDestroyInstance(inst, nullptr);
  return out;
}

VkBool32 Context::on_message(VkDebugUtilsMessageSeverityFlagBitsEXT sev, VkDebugUtilsMessageTypeFlagsEXT,
                             const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* self = static_cast<Context*>(user);
  if (sev & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
    self->validation_errors_++;
    fmt::print(stderr, "[vulkan validation error] {}\n", data->pMessage);
  } else if (sev & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    fmt::print(stderr, "[vulkan validation warning] {}\n", data->pMessage);
  }
  return VK_FALSE;
}

Context::Context(const ContextOptions& opt) {
  const char* env_val = std::getenv("WETDEM_VALIDATION");
  bool validation = opt.validation || (env_val && std::string(env_val) == "1");
  if (validation && !has_layer("VK_LAYER_KHRONOS_validation"))
    throw std::runtime_error(
        "validation requested but VK_LAYER_KHRONOS_validation is not installed (apt-get install "
        "vulkan-validationlayers)");
  instance_ = make_instance(validation);
  if (validation) {
    VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mi.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
    mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    mi.pfnUserCallback = &Context::on_message;
    mi.pUserData = this;
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (!create) throw std::runtime_error("vkCreateDebugUtilsMessengerEXT not available");
    WETDEM_VK(create(instance_, &mi, nullptr, &messenger_));
  }

  auto devs = physical_devices(instance_);
  if (devs.empty())
    throw std::runtime_error("no Vulkan device found (install mesa-vulkan-drivers for lavapipe)");
  std::string want = opt.device;
  if (want.empty()) {
    const char* e = std::getenv("WETDEM_DEVICE");
    if (e) want = e;
  }
  want = lower(want);
  std::vector<VkPhysicalDeviceProperties> props(devs.size());
  for (size_t i = 0; i < devs.size(); ++i) vkGetPhysicalDeviceProperties(devs[i], &props[i]);
  int chosen = -1;
  if (want.empty() || want == "auto" || want == "gpu") {
    for (size_t i = 0; i < devs.size(); ++i)
      if (chosen < 0 || type_rank(props[i].deviceType) < type_rank(props[chosen].deviceType)) chosen = int(i);
    if (want == "gpu" && props[chosen].deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU)
      throw std::runtime_error("device 'gpu' requested but only CPU (lavapipe) devices are present");
  } else if (want == "cpu" || want == "lavapipe" || want == "llvmpipe") {
    for (size_t i = 0; i < devs.size(); ++i)
      if (props[i].deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) chosen = int(i);
  } else if (std::all_of(want.begin(), want.end(), ::isdigit)) {
    size_t k = std::stoul(want);
    if (k < devs.size()) chosen = int(k);
  } else {
    for (size_t i = 0; i < devs.size(); ++i)
      if (lower(props[i].deviceName).find(want) != std::string::npos) {
        chosen = int(i);
        break;
      }
  }
  if (chosen < 0) {
    std::string all;
    for (size_t i = 0; i < devs.size(); ++i) all += fmt::format(" [{}] {}", i, props[i].deviceName);
    throw std::runtime_error(fmt::format("device '{}' not found; devices:{}", want, all));
  }
  phys_ = devs[chosen];

  VkPhysicalDeviceDriverProperties drv{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceSubgroupProperties sub{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  sub.pNext = &drv;
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  p2.pNext = &sub;
  vkGetPhysicalDeviceProperties2(phys_, &p2);
  info_.name = p2.properties.deviceName;
  info_.driver_name = drv.driverName;
  info_.driver_info = drv.driverInfo;
  info_.type = p2.properties.deviceType;
  info_.subgroup_size = sub.subgroupSize;
  info_.timestamp_period_ns = p2.properties.limits.timestampPeriod;
  vkGetPhysicalDeviceMemoryProperties(phys_, &mem_);

  // Required features: int64 in shaders (liquid volumes), buffer device address (buffer table).
  VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  f2.pNext = &f12;
  vkGetPhysicalDeviceFeatures2(phys_, &f2);
  if (!f2.features.shaderInt64) throw std::runtime_error(info_.name + ": shaderInt64 is not supported");
  if (!f12.bufferDeviceAddress)
    throw std::runtime_error(info_.name + ": bufferDeviceAddress is not supported");
  if (!f12.scalarBlockLayout) throw std::runtime_error(info_.name + ": scalarBlockLayout is not supported");
  // Optional: 64-bit integer atomics on buffers (the fused step's liquid passes; without them the step is
  // recorded pass by pass, host/gpu/system.cpp).
  info_.int64_atomics = f12.shaderBufferInt64Atomics == VK_TRUE;

  uint32_t nq = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(phys_, &nq, nullptr);
  std::vector<VkQueueFamilyProperties> qf(nq);
  vkGetPhysicalDeviceQueueFamilyProperties(phys_, &nq, qf.data());
  bool found = false;
  for (uint32_t i = 0; i < nq; ++i)
    if (qf[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
      family_ = i;
      found = true;
      info_.timestamps = qf[i].timestampValidBits > 0 && info_.timestamp_period_ns > 0;
      break;
    }
  if (!found) throw std::runtime_error(info_.name + ": no compute queue");

  float prio = 1.0f;
  VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = family_;
  qci.queueCount = 1;
  qci.pQueuePriorities = &prio;
  VkPhysicalDeviceVulkan12Features en12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  en12.bufferDeviceAddress = VK_TRUE;
  en12.shaderBufferInt64Atomics = info_.int64_atomics ? VK_TRUE : VK_FALSE;
  en12.scalarBlockLayout = VK_TRUE;
  VkPhysicalDeviceFeatures2 en{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  en.pNext = &en12;
  en.features.shaderInt64 = VK_TRUE;
  VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  dci.pNext = &en;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  WETDEM_VK(vkCreateDevice(phys_, &dci, nullptr, &device_));
  vkGetDeviceQueue(device_, family_, 0, &queue_);

  VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pci.queueFamilyIndex = family_;
  WETDEM_VK(vkCreateCommandPool(device_, &pci, nullptr, &pool_));
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  WETDEM_VK(vkCreateFence(device_, &fci, nullptr, &fence_));

  // One pipeline layout for every kernel: the push constants and set 0, two uniform buffers (the buffer
  // table and the parameters, shaders/common/access.glsl). Uniform-buffer reads at a uniform offset are
  // one load for all invocations (lavapipe loads device addresses lane by lane); kernels that declare no
  // set ignore it, and the set stays bound across their pipelines.
  VkDescriptorSetLayoutBinding b[2]{};
  for (uint32_t k = 0; k < 2; ++k) {
    b[k].binding = k;
    b[k].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    b[k].descriptorCount = 1;
    b[k].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo dl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  dl.bindingCount = 2;
  dl.pBindings = b;
  WETDEM_VK(vkCreateDescriptorSetLayout(device_, &dl, nullptr, &set_layout_));
  VkPushConstantRange pr{VK_SHADER_STAGE_COMPUTE_BIT, 0, kPushConstantBytes};
  VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  li.setLayoutCount = 1;
  li.pSetLayouts = &set_layout_;
  li.pushConstantRangeCount = 1;
  li.pPushConstantRanges = &pr;
  WETDEM_VK(vkCreatePipelineLayout(device_, &li, nullptr, &pipeline_layout_));

  if (!opt.quiet) fmt::print("wetdem: device {}\n", info_.describe());
}

Context::~Context() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    vkDestroyPipelineLayout(device_, pipeline_layout_, nullptr);
    vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
    vkDestroyFence(device_, fence_, nullptr);
    vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

uint32_t Context::memory_type(uint32_t type_bits, VkMemoryPropertyFlags want) const {
  for (uint32_t i = 0; i < mem_.memoryTypeCount; ++i)
    if ((type_bits & (1u << i)) && (mem_.memoryTypes[i].propertyFlags & want) == want) return i;
  throw std::runtime_error("no suitable Vulkan memory type");
}

VkCommandBuffer Context::begin_one_shot() {
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cb;
  WETDEM_VK(vkAllocateCommandBuffers(device_, &ai, &cb));
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  WETDEM_VK(vkBeginCommandBuffer(cb, &bi));
  return cb;
}

void Context::end_one_shot(VkCommandBuffer cb) {
  WETDEM_VK(vkEndCommandBuffer(cb));
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cb;
  WETDEM_VK(vkResetFences(device_, 1, &fence_));
  WETDEM_VK(vkQueueSubmit(queue_, 1, &si, fence_));
  WETDEM_VK(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX));
  vkFreeCommandBuffers(device_, pool_, 1, &cb);
}

}  // namespace wetdem::vk
