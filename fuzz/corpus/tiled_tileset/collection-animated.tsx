<?xml version="1.0" encoding="UTF-8"?>
<tileset version="1.10" name="things" tilewidth="6" tileheight="5" tilecount="3" columns="0" objectalignment="center" tilerendersize="grid" fillmode="stretch">
 <tileoffset x="2" y="-1"/>
 <tile id="0"><image source="a.png" width="3" height="5"/></tile>
 <tile id="3" x="1" y="0" width="4" height="2"><image source="b.png" width="6" height="2"/></tile>
 <tile id="7"><animation><frame tileid="3" duration="100"/><frame tileid="0" duration="100"/></animation></tile>
</tileset>
