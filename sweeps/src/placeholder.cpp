// placeholder until the grid code lands
namespace occsweep {}
