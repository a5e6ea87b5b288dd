#include "igtl/igtl_client.h"

#include <chrono>
#include <cstring>
#include <thread>

#include "igtlClientSocket.h"
#include "igtlImageMessage.h"
#include "igtlMessageHeader.h"
#include "igtlPolyDataMessage.h"
#include "igtlStringMessage.h"
#include "igtlTimeStamp.h"
#include "igtlTransformMessage.h"

namespace osteon::test {

namespace {

double wallS() {
  ::igtl::TimeStamp::Pointer ts = ::igtl::TimeStamp::New();
  ts->GetTime();
  return ts->GetTimeStamp();
}

void applyImage(::igtl::ImageMessage& img, IgtlReceived& r) {
  int dims[3], sub[3], off[3];
  img.GetDimensions(dims);
  img.GetSubVolume(sub, off);
  img.GetSpacing(r.spacing);
  const glm::ivec3 d(dims[0], dims[1], dims[2]);
  if (r.dims != d) {
    r.dims = d;
    r.volume.assign(std::size_t(d.x) * std::size_t(d.y) * std::size_t(d.z), 0);
  }
  const bool whole = sub[0] == dims[0] && sub[1] == dims[1] && sub[2] == dims[2];
  (whole ? r.wholeVolumes : r.subVolumes) += 1;
  const auto* in = static_cast<const std::uint8_t*>(img.GetScalarPointer());
  std::size_t at = 0;
  for (int z = off[2]; z < off[2] + sub[2]; ++z) {
    for (int y = off[1]; y < off[1] + sub[1]; ++y) {
      for (int x = off[0]; x < off[0] + sub[0]; ++x) {
        r.volume[std::size_t(x) +
                 std::size_t(d.x) * (std::size_t(y) + std::size_t(d.y) * std::size_t(z))] =
            in[at++];
      }
    }
  }
}

template <typename M>
typename M::Pointer body(::igtl::Socket& socket, ::igtl::MessageHeader::Pointer& header) {
  typename M::Pointer m = M::New();
  m->SetMessageHeader(header);
  m->AllocatePack();
  socket.Receive(m->GetPackBodyPointer(), m->GetPackBodySize());
  m->Unpack(1);
  return m;
}

}  // namespace

IgtlReceived receiveAll(int port, bool getPolyData) {
  IgtlReceived r;
  ::igtl::ClientSocket::Pointer socket = ::igtl::ClientSocket::New();
  for (int i = 0; i < 3000 && socket->ConnectToServer("127.0.0.1", port) != 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (getPolyData) {
    ::igtl::GetPolyDataMessage::Pointer get = ::igtl::GetPolyDataMessage::New();
    get->SetDeviceName("BoneSurface");
    get->Pack();
    socket->Send(get->GetPackPointer(), get->GetPackSize());
  }
  for (;;) {
    ::igtl::MessageHeader::Pointer header = ::igtl::MessageHeader::New();
    header->InitPack();
    if (socket->Receive(header->GetPackPointer(), header->GetPackSize()) != header->GetPackSize())
      break;
    header->Unpack();
    const std::string type = header->GetDeviceType();
    ::igtl::TimeStamp::Pointer sent = ::igtl::TimeStamp::New();
    header->GetTimeStamp(sent);
    if (type == "IMAGE") {
      applyImage(*body<::igtl::ImageMessage>(*socket, header), r);
    } else if (type == "TRANSFORM") {
      auto t = body<::igtl::TransformMessage>(*socket, header);
      ::igtl::Matrix4x4 m;
      t->GetMatrix(m);
      ReceivedTransform rt;
      for (int row = 0; row < 4; ++row) {
        for (int c = 0; c < 4; ++c) rt.matrix[c][row] = double(m[row][c]);
      }
      rt.latencyS = wallS() - sent->GetTimeStamp();
      r.transforms.push_back(rt);
    } else if (type == "STRING") {
      auto s = body<::igtl::StringMessage>(*socket, header);
      r.strings.push_back(std::string(header->GetDeviceName()) + "=" + s->GetString());
    } else if (type == "POLYDATA") {
      body<::igtl::PolyDataMessage>(*socket, header);
      r.polydata.push_back(header->GetDeviceName());
    } else {
      socket->Skip(static_cast<int>(header->GetBodySizeToRead()), 0);
    }
    const double now = wallS();
    if (r.messages == 0) r.firstS = now;
    r.lastS = now;
    ++r.messages;
    r.bytes += 58u + static_cast<std::uint64_t>(header->GetBodySizeToRead());
    r.latenciesS.push_back(now - sent->GetTimeStamp());
  }
  socket->CloseSocket();
  return r;
}

}  // namespace osteon::test
