# Sourced by scripts/setup.sh and scripts/fuzz.sh: the Debian packages skidsim
# builds with, and the idempotent installer (as root, or through sudo).

SKIDSIM_PACKAGES=(
  build-essential cmake pkg-config
  libeigen3-dev          # terrain, geometry
  libpng-dev             # height maps, images
  libtinyxml2-dev        # soil table, exercises
  nlohmann-json3-dev     # metadata, summaries, reports
  libcli11-dev           # the skidsim command line
  libgtest-dev libgmock-dev  # tests
  libbenchmark-dev       # skidsim bench
  libbullet-dev          # the loader's multibody (double build: bullet-float64)
  liburdfdom-dev         # the loader's URDF
  libassimp-dev          # visual meshes
  liblcm-dev liblcm-bin libglib2.0-dev  # LCM: messages, lcm-gen, lcm-logger (pkg-config lcm needs glib)
  libegl-dev libegl-mesa0 libgl1-mesa-dri libgl-dev  # off-screen OpenGL: EGL, Mesa's drivers, GL headers
  libosmesa6-dev         # off-screen OpenGL: the OSMesa fallback
  ffmpeg                 # recorded frames -> session.mp4
  libcpp-httplib-dev     # the live station's HTTP server
  libturbojpeg0-dev      # the live station's JPEG frames
  chromium-headless-shell  # the review page's and the station's tests (a real browser)
)

# install_packages WHO PACKAGE...: installs those not installed yet.
install_packages() {
  local who=$1
  shift
  local missing=() p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    local sudo=()
    if [[ $(id -u) -ne 0 ]]; then sudo=(sudo); fi
    echo "$who: installing ${missing[*]}"
    "${sudo[@]}" apt-get update -qq
    DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
}
