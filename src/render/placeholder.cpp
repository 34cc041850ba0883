// STUB: replaced by the headless renderer (issue 5).
namespace depthcull {}
